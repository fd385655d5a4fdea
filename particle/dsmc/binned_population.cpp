#include "particle/dsmc/binned_population.hpp"

#include <algorithm>

namespace aggkit::dsmc {

BinnedPopulation::BinnedPopulation(std::uint64_t bucket_limit)
    : limit_(bucket_limit), bucket_(bucket_limit + 1, 0), fenwick_(bucket_limit) {}

BinnedPopulation::Bin& BinnedPopulation::bin_for(std::uint64_t size) {
  const std::size_t b = bin_of(size);
  if (b >= bins_.size()) bins_.resize(b + 1);
  return bins_[b];
}

void BinnedPopulation::add(std::uint64_t size, std::uint64_t copies) {
  if (copies == 0) return;
  Bin& bin = bin_for(size);
  bin.count += copies;
  particles_ += copies;
  if (size <= limit_) {
    bin.small += copies;
    bucket_[size] += copies;
    fenwick_.add(size, std::int64_t(copies));
  } else {
    bin.large.insert(bin.large.end(), copies, size);
  }
}

BinnedPopulation::Pick BinnedPopulation::pick(std::size_t b, std::uint64_t rank) const {
  const Bin& bin = bins_[b];
  if (rank < bin.small) {
    const std::uint64_t low = bin_low(b);
    if (low == bin_high(b)) return {b, low, npos};
    return {b, fenwick_.select(fenwick_.prefix(low - 1) + rank), npos};
  }
  const std::size_t index = std::size_t(rank - bin.small);
  return {b, bin.large[index], index};
}

void BinnedPopulation::remove(const Pick& particle) {
  Bin& bin = bins_[particle.bin];
  --bin.count;
  --particles_;
  if (particle.large_index == npos) {
    --bin.small;
    --bucket_[particle.size];
    fenwick_.add(particle.size, -1);
  } else {
    bin.large[particle.large_index] = bin.large.back();
    bin.large.pop_back();
  }
}

void BinnedPopulation::duplicate() {
  for (auto& count : bucket_) count *= 2;
  fenwick_.scale(2);
  for (auto& bin : bins_) {
    bin.count *= 2;
    bin.small *= 2;
    const std::size_t n = bin.large.size();
    bin.large.reserve(2 * n);
    for (std::size_t i = 0; i < n; ++i) bin.large.push_back(bin.large[i]);
  }
  particles_ *= 2;
}

void BinnedPopulation::for_each_group(const std::function<void(std::uint64_t, std::uint64_t)>& f) const {
  for (std::uint64_t s = 1; s <= limit_; ++s)
    if (bucket_[s] != 0) f(s, bucket_[s]);
  for (const auto& bin : bins_)
    for (std::uint64_t size : bin.large) f(size, 1);
}

}  // namespace aggkit::dsmc

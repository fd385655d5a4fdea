#include "particle/dsmc/binned_population.hpp"

#include <algorithm>

#include "particle/dsmc/population_control.hpp"

namespace aggkit::dsmc {

BinnedPopulation::BinnedPopulation(std::uint64_t bucket_limit)
    : limit_(bucket_limit), bucket_(bucket_limit + 1, 0) {
  for (std::size_t b = 0; bucket_limit > 0 && bin_low(b) <= bucket_limit; ++b) {
    const std::uint64_t low = bin_low(b), high = bucketed_high(b);
    trees_.emplace_back();
    if (high - low >= narrow_bin) trees_.back().emplace(high - low + 1);
  }
}

void BinnedPopulation::rebuild_trees() {
  for (std::size_t b = 0; b < trees_.size(); ++b)
    if (trees_[b]) trees_[b]->assign(bucket_.data() + (bin_low(b) - 1));  // the bin's sizes as indices 1..width
}

void BinnedPopulation::duplicate() {
  for (auto& count : bucket_) count *= 2;
  for (auto& tree : trees_)
    if (tree) tree->scale(2);
  for (auto& bin : bins_) {
    bin.count *= 2;
    bin.small *= 2;
    const std::size_t n = bin.large.size();
    bin.large.reserve(2 * n);
    for (std::size_t i = 0; i < n; ++i) bin.large.push_back(bin.large[i]);
  }
  particles_ *= 2;
}

void BinnedPopulation::halve(Random& random) {
  // Buckets in increasing size, then the individual particles bin by bin (increasing sizes again).
  for (auto& bin : bins_) bin.count = bin.small = 0;
  particles_ = 0;
  for (std::uint64_t s = 1; s <= limit_; ++s) {
    if (bucket_[s] == 0) continue;
    bucket_[s] = halve_count(bucket_[s], random);
    Bin& bin = bins_[bin_of(s)];
    bin.count += bucket_[s];
    bin.small += bucket_[s];
    particles_ += bucket_[s];
  }
  rebuild_trees();
  for (auto& bin : bins_) {
    halve_sizes(bin.large, random);
    bin.count += bin.large.size();
    particles_ += bin.large.size();
  }
}

void BinnedPopulation::for_each_group(const std::function<void(std::uint64_t, std::uint64_t)>& f) const {
  for (std::uint64_t s = 1; s <= limit_; ++s)
    if (bucket_[s] != 0) f(s, bucket_[s]);
  for (const auto& bin : bins_)
    for (std::uint64_t size : bin.large) f(size, 1);
}

}  // namespace aggkit::dsmc

#include "particle/dsmc/fast_dsmc.hpp"

#include <algorithm>

#include "particle/dsmc/population_control.hpp"

namespace aggkit::dsmc {

FastDsmc::FastDsmc(InteractionKernel kernel, std::uint64_t bucket_limit)
    : kernel_(kernel), limit_(bucket_limit), slot_(bucket_limit + 1, npos) {}

void FastDsmc::change(std::uint64_t size, std::int64_t delta, std::size_t group) {
  if (delta == 0) return;
  // Every particle's S gains delta K(s_g, size); the changed group's own particles do not count themselves.
  for (auto& g : groups_) g.rate += double(delta) * kernel_(g.size, size);
  if (size <= limit_) group = slot_[size];
  if (delta > 0 && group == npos) {
    // A new group: its rate from scratch (the loop above did not see it).
    Group g{size, 0, 0.0};
    for (const auto& other : groups_) g.rate += double(other.count) * kernel_(size, other.size);
    if (size <= limit_) slot_[size] = groups_.size();
    groups_.push_back(g);
    group = groups_.size() - 1;
    // Its own copies are partners of each other: S counts the others of the same size.
    groups_[group].rate += double(delta - 1) * kernel_(size, size);
    groups_[group].count = std::uint64_t(delta);
  } else {
    // The loop above also updated this group: its particles see delta more (or fewer) of their size.
    Group& g = groups_[group];
    g.count = std::uint64_t(std::int64_t(g.count) + delta);
    if (g.count == 0) remove_group(group);
  }
  particles_ = std::uint64_t(std::int64_t(particles_) + delta);
}

void FastDsmc::remove_group(std::size_t group) {
  if (groups_[group].size <= limit_) slot_[groups_[group].size] = npos;
  if (group + 1 != groups_.size()) {
    groups_[group] = groups_.back();
    if (groups_[group].size <= limit_) slot_[groups_[group].size] = group;
  }
  groups_.pop_back();
}

void FastDsmc::recompute_rates() {
  for (auto& g : groups_) {
    double sum = -kernel_(g.size, g.size);
    for (const auto& other : groups_) sum += double(other.count) * kernel_(g.size, other.size);
    g.rate = sum;
  }
  events_since_refresh_ = 0;
}

double FastDsmc::trial_weight() {
  double total = 0.0;
  for (const auto& g : groups_) total += double(g.count) * std::max(0.0, g.rate);
  total_weight_ = total;
  return total;
}

TrialOutcome FastDsmc::trial(double lambda, Random& random) {
  // First particle: group g with probability n_g S_g / Σ n S (all particles of a group share S).
  double u = random.uniform() * total_weight_;
  std::size_t first = 0, last = npos;
  for (; first < groups_.size(); ++first) {
    const double w = double(groups_[first].count) * std::max(0.0, groups_[first].rate);
    if (w <= 0.0) continue;
    last = first;
    if (u < w) break;
    u -= w;
  }
  if (first == groups_.size()) first = last;
  if (first == npos) return TrialOutcome::rejected;
  // Partner: group h with probability (n_h - δ_gh) K(s_g, s_h) / S_g, by the exact kernel.
  const std::uint64_t s = groups_[first].size;
  double v = random.uniform() * groups_[first].rate;
  std::size_t second = 0;
  last = npos;
  for (; second < groups_.size(); ++second) {
    const std::uint64_t others = groups_[second].count - (second == first ? 1 : 0);
    const double w = double(others) * kernel_(s, groups_[second].size);
    if (w <= 0.0) continue;
    last = second;
    if (v < w) break;
    v -= w;
  }
  if (second == groups_.size()) second = last;
  if (second == npos) return TrialOutcome::rejected;
  const std::uint64_t r = groups_[second].size;
  const std::uint64_t merged = s + r;
  const bool shatter = random.uniform() * (1.0 + lambda) >= 1.0;  // probability λ / (1+λ)

  // Remove the pair: individually stored particles are addressed by group (the higher index first).
  const std::size_t high = std::max(first, second), low = std::min(first, second);
  if (first == second) {
    change(s, -2, first);
  } else {
    change(groups_[high].size, -1, high);
    change(groups_[low].size, -1, low);
  }
  TrialOutcome outcome;
  if (shatter) {
    change(1, std::int64_t(merged));
    outcome = TrialOutcome::shattered;
  } else if (kernel_.leaves(merged)) {
    leaked_ += merged;
    outcome = TrialOutcome::leaked;
  } else {
    change(merged, 1);
    outcome = TrialOutcome::aggregated;
  }
  // Incremental rates drift by round-off: refresh them after about D events (amortised O(D) per event).
  if (++events_since_refresh_ >= std::max<std::size_t>(groups_.size(), 1024)) recompute_rates();
  return outcome;
}

void FastDsmc::duplicate() {
  // Doubling every particle: S' = Σ_{j != i} over the doubled set = 2 (S + K(s, s)) - K(s, s).
  const std::size_t n = groups_.size();
  for (std::size_t g = 0; g < n; ++g) {
    groups_[g].rate = 2.0 * groups_[g].rate + kernel_(groups_[g].size, groups_[g].size);
    if (groups_[g].size <= limit_) {
      groups_[g].count *= 2;
    } else {
      const Group copy = groups_[g];  // an individual particle gets an individual copy
      groups_.push_back(copy);
    }
  }
  particles_ *= 2;
  leaked_ *= 2;
}

void FastDsmc::halve(Random& random) {
  // Counts per size (bucketed groups and individual particles alike), halved in increasing size order; the
  // groups and their rates are then rebuilt (O(D^2) kernel evaluations, once per halving).
  std::vector<std::pair<std::uint64_t, std::uint64_t>> counts;
  for (const auto& g : groups_) counts.push_back({g.size, g.count});
  std::sort(counts.begin(), counts.end());
  groups_.clear();
  std::fill(slot_.begin(), slot_.end(), npos);
  particles_ = 0;
  for (std::size_t i = 0; i < counts.size();) {
    std::uint64_t count = 0;
    std::size_t j = i;
    for (; j < counts.size() && counts[j].first == counts[i].first; ++j) count += counts[j].second;
    const std::uint64_t size = counts[i].first, kept = halve_count(count, random);
    if (size <= limit_) {
      if (kept > 0) groups_.push_back({size, kept, 0.0});
      if (kept > 0) slot_[size] = groups_.size() - 1;
    } else {
      for (std::uint64_t k = 0; k < kept; ++k) groups_.push_back({size, 1, 0.0});
    }
    particles_ += kept;
    i = j;
  }
  leaked_ = halve_count(leaked_, random);
  recompute_rates();
}

void FastDsmc::for_each_group(const std::function<void(std::uint64_t, std::uint64_t)>& f) const {
  for (const auto& g : groups_) f(g.size, g.count);
}

}  // namespace aggkit::dsmc

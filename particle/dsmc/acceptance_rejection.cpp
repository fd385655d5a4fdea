#include "particle/dsmc/acceptance_rejection.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "particle/dsmc/population_control.hpp"

namespace aggkit::dsmc {

AcceptanceRejection::AcceptanceRejection(InteractionKernel kernel, std::uint64_t bucket_limit)
    : kernel_(kernel), table_(kernel_), population_(bucket_limit), majorant_(max_bins * max_bins, 0.0),
      counts_(max_bins, 0) {}

void AcceptanceRejection::ensure_bins(std::size_t bins) {
  for (; known_ < bins; ++known_) {
    const std::size_t c = known_;
    const std::uint64_t c_low = bin_low(c), c_high = bin_high(c);
    for (std::size_t b = 0; b <= c; ++b) {
      const std::uint64_t b_low = bin_low(b), b_high = bin_high(b);
      double bound = 0.0;
      // A cutoff forbids every pair of the two bins when even the smallest sizes exceed it.
      if (kernel_.cutoff() == 0 || b_low + c_low <= kernel_.cutoff())
        bound = std::max({kernel_.raw(b_low, c_low), kernel_.raw(b_low, c_high), kernel_.raw(b_high, c_low),
                          kernel_.raw(b_high, c_high)});
      majorant_[b * max_bins + c] = majorant_[c * max_bins + b] = bound;
    }
  }
}

const std::uint64_t* AcceptanceRejection::counts() {
  const std::size_t n = population_.bins();
  for (std::size_t b = 0; b < n; ++b) counts_[b] = population_.count(b);
  return counts_.data();
}

void AcceptanceRejection::rebuild() {
  const std::uint64_t* n = counts();
  slots_.set_capacities(n, population_.bins());
  slots_.build(majorant_.data(), n);
  dirty_ = false;
}

void AcceptanceRejection::insert(std::uint64_t size, std::uint64_t count) {
  if (count == 0) return;  // no bin to touch (the population may not have it yet)
  const std::size_t bin = bin_of(size);
  if (bin >= known_) ensure_bins(bin + 1);
  population_.add(size, count);
  touched(bin);
}

void AcceptanceRejection::add(std::uint64_t size, std::uint64_t count) { insert(size, count); }

double AcceptanceRejection::trial_weight() {
  if (dirty_) rebuild();
  return slots_.particles_interact() ? slots_.total() : 0.0;
}

TrialOutcome AcceptanceRejection::trial(double lambda, Random& random) {
  // A slot pair of the majorant process (slot_majorant.hpp); a pair with an empty slot is rejected.
  const std::size_t b = slots_.first(random.uniform());
  const std::uint64_t first_rank = random.below(slots_.capacity(b));
  if (first_rank >= population_.count(b)) return TrialOutcome::rejected;
  const std::size_t c = slots_.second(b, random.uniform());
  std::uint64_t second_rank;
  if (c == b) {  // another slot of the same bin
    second_rank = random.below(slots_.capacity(b) - 1);
    if (second_rank >= first_rank) ++second_rank;
  } else {
    second_rank = random.below(slots_.capacity(c));
  }
  if (second_rank >= population_.count(c)) return TrialOutcome::rejected;
  const auto p = population_.pick(b, first_rank);
  const auto q = population_.pick(c, second_rank);

  const double k = table_(p.size, q.size);
  const double majorant = bound(b, c);
  if (k > majorant * (1.0 + 1e-12))
    throw std::runtime_error("dsmc: kernel K(" + std::to_string(p.size) + ", " + std::to_string(q.size) +
                             ") exceeds its bin majorant; the kernel is not quasi-convex in each size");
  // One uniform number decides all three outcomes ([Kalinov2022, Sec. 3]): u' in [0, (1+λ) K̄).
  const double x = random.uniform() * (1.0 + lambda) * majorant;
  if (!(x < (1.0 + lambda) * k)) return TrialOutcome::rejected;

  // Remove the pair (two individually stored particles of one bin: the higher index first).
  if (p.bin == q.bin && p.large_index != BinnedPopulation::npos && q.large_index != BinnedPopulation::npos &&
      p.large_index < q.large_index) {
    population_.remove(q);
    population_.remove(p);
  } else {
    population_.remove(p);
    population_.remove(q);
  }
  const std::uint64_t merged = p.size + q.size;
  TrialOutcome outcome;
  if (x < k) {
    if (kernel_.leaves(merged)) {
      leaked_ += merged;
      outcome = TrialOutcome::leaked;
    } else {
      insert(merged, 1);
      outcome = TrialOutcome::aggregated;
    }
  } else {
    insert(1, merged);  // shattering: i + j monomers, one bucket update
    outcome = TrialOutcome::shattered;
  }
  touched(p.bin);  // the counts after the whole event: a cluster that stays in its bin changes nothing
  touched(q.bin);
  return outcome;
}

void AcceptanceRejection::duplicate() {
  population_.duplicate();
  leaked_ *= 2;
  dirty_ = true;
}

void AcceptanceRejection::halve(Random& random) {
  population_.halve(random);
  leaked_ = halve_count(leaked_, random);
  dirty_ = true;
}

}  // namespace aggkit::dsmc

#pragma once
// One DSMC method: the population and how a trial is drawn. Time is advanced by the driver
// (simulation.hpp): each trial takes τ = 2V / ((1+λ) W), where W is the stepper's ordered-pair sum of the
// rates it samples from (the majorant for acceptance-rejection, the exact rates for fast DSMC), so that
// trials form a process of rate (1+λ) W / (2V) and accepted pairs one of rate (1+λ) Σ_{i<j} K_ij / V
// ([Kalinov2022, eq. 7]: τ = 2 / (n̂ (N-1) K_max (1+λ)) for a single global bound K_max).
#include <cstdint>
#include <functional>

#include "particle/common/checkpoint.hpp"
#include "particle/dsmc/interaction.hpp"
#include "particle/dsmc/random.hpp"

namespace aggkit::dsmc {

class Stepper {
 public:
  virtual ~Stepper() = default;
  virtual void add(std::uint64_t size, std::uint64_t count) = 0;  // builds the initial population
  // W = Σ_{i != j} (sampling rate of the ordered pair); 0 when no pair can interact.
  virtual double trial_weight() = 0;
  // One trial at shattering rate λ: picks a pair, accepts, merges or shatters it.
  virtual TrialOutcome trial(double lambda, Random& random) = 0;
  virtual void duplicate() = 0;  // population control: every particle doubled
  // Population control in reverse: particles of equal size are paired and one of each pair is removed; the
  // odd one out of a size is kept with probability 1/2 (coins drawn in increasing size order, so a run stays
  // reproducible). Each particle survives with probability exactly 1/2, so E[count_k after] = count_k / 2 for
  // every size k: with the volume halved the expected densities are unchanged. The leaked mass is halved the
  // same way. See halve_counts (population_control.hpp).
  virtual void halve(Random& random) = 0;
  virtual std::uint64_t particles() const = 0;
  virtual void for_each_group(const std::function<void(std::uint64_t size, std::uint64_t count)>& f) const = 0;
  virtual std::uint64_t leaked_mass() const = 0;  // mass of merged clusters removed by a `drop` truncation
  // Checkpoints: the population and every running sum as they are (sums rebuilt afresh would round
  // differently, and the run would not continue to the same bits); restore() into a stepper built for the
  // same model and options.
  virtual void save(StateWriter& out) const = 0;
  virtual void restore(StateReader& in) = 0;
};

}  // namespace aggkit::dsmc

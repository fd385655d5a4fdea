#pragma once
// One DSMC realisation of the aggregation-shattering model [Kalinov2022]: the initial densities become
// N(0) particles in the volume V = N(0) / Σ_k n_k(0); trials of the chosen method (stepper.hpp) advance
// the time by τ = 2V / ((1+λ(t)) W) each. Population control ([Kalinov2022, Sec. 2]; [Liffman1992]):
// when N(t) < N(0)/2 every particle is duplicated and V doubles, so densities are unchanged; when shattering
// drives N(t) above 2 N(0) the population is halved by pairs of equal size (Stepper::halve: every particle
// survives with probability 1/2, so expected densities are unchanged) and V halves. A doubling keeps the mass
// exactly (×2); a halving keeps it in expectation (×1/2, off by at most half the odd ones out, one per size).
// Between population-control events aggregation and shattering conserve the integer mass exactly. A population
// where no pair can interact any more (one cluster left — "extinction" [Kalinov2022, Sec. 5.2] — or, under
// a cutoff, only pairs beyond it) is frozen and reported, not looped on.
#include <cstdint>
#include <functional>
#include <memory>

#include "particle/dsmc/options.hpp"
#include "particle/dsmc/random.hpp"
#include "particle/dsmc/snapshot.hpp"
#include "particle/dsmc/stepper.hpp"
#include "solvers/model.hpp"

namespace aggkit::dsmc {

struct RunStatistics {
  std::uint64_t trials = 0;
  std::uint64_t aggregations = 0;
  std::uint64_t shatterings = 0;
  std::uint64_t leaks = 0;           // merged clusters removed by a `drop` truncation
  std::uint64_t doublings = 0;       // population-control duplications
  std::uint64_t halvings = 0;        // population-control halvings (N(t) > 2 N(0))
  bool extinct = false;              // one cluster left
  bool frozen = false;               // no pair can interact (extinct, or every pair beyond a cutoff)
  double frozen_time = 0.0;          // when that was found
  std::uint64_t accepted() const { return aggregations + shatterings + leaks; }
};

class Simulation {
 public:
  // Validates the options (Options::validate) and the model on [0, t_end] (negative λ, bad tables).
  Simulation(const AggregationModel& model, const Options& options, std::uint64_t seed, double t_end);
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // t >= time(); the state at t. `every`, if given, is called with the current time every 2^20 trials (for
  // progress and budgets; it may throw to stop the run). Advancing in several calls gives the same run.
  void advance_to(double t, const std::function<void(double time)>& every = {});
  double time() const { return time_; }
  Snapshot snapshot() const;
  const RunStatistics& statistics() const { return statistics_; }
  double volume() const { return volume_; }
  std::uint64_t initial_particles() const { return initial_particles_; }
  // Σ k count_k plus the leaked mass, exact: equals initial mass × 2^doublings while no halving happened, and
  // control_mass() from one population-control event to the next.
  std::uint64_t mass() const;
  std::uint64_t control_mass() const { return control_mass_; }  // mass() right after the last control event
  std::uint64_t initial_mass() const { return initial_mass_; }
  // Checkpoints: the population, the running sums, the random generator's state, the clock and the
  // counters; restore() into a Simulation built with the same model, options, seed and end continues to
  // the same bits.
  void save(StateWriter& out) const;
  void restore(StateReader& in);

 private:
  // The trials up to t (advance_to) with the stepper's own type, so a final stepper's calls are direct.
  template <class StepperType>
  void run_trials(StepperType& stepper, double t, const std::function<void(double time)>& every);
  bool no_pair_can_interact() const;  // exact check, for the cutoff watchdog
  void freeze();

  AggregationModel model_;  // owned: the stepper's kernel refers to model_.kernel
  Options options_;
  std::unique_ptr<Stepper> stepper_;
  Random random_;
  double time_ = 0.0;
  double volume_ = 1.0;
  double next_trial_ = -1.0;   // time of the scheduled trial; < time_ when none is scheduled
  double next_lambda_ = 0.0;   // λ at scheduling
  bool lambda_is_constant_ = false;  // then λ(t) = constant_lambda_, read once (one trial is ~100 ns)
  double constant_lambda_ = 0.0;
  // The last time step and what it was computed from: the stepper's weight changes only now and then
  // (slot_majorant.hpp), so the division is skipped while weight, volume and λ stay the same.
  struct Step {
    double weight = 0.0, volume = 0.0, lambda = 0.0, step = 0.0;
  } step_;
  std::uint64_t initial_particles_ = 0;
  std::uint64_t initial_mass_ = 0;
  std::uint64_t control_mass_ = 0;
  std::uint64_t rejections_in_a_row_ = 0;
  RunStatistics statistics_;
};

// Integer particle counts for densities n (n[k-1] of size k) scaled to `particles` in total: floor of
// n_k V, the remainder given to the largest fractional parts (smaller sizes first on ties).
std::vector<std::uint64_t> initial_counts(const std::vector<double>& n, std::uint64_t particles);

}  // namespace aggkit::dsmc

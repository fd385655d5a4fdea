#pragma once
// A weakly attracting limit cycle reached by extrapolating its Poincaré map instead of waiting for it. Near a
// supercritical Hopf point the cycle attracts at the radial rate 2 Re μ, a multiplier e^{-2 Re μ T} per period: at
// brownian a = 0.6 and 0.95 λ_crit (graded grid to 2^40, period 5e6) a start on the normal form's cycle needs
// ln(1e3)/(2 Re μ) ≈ 1000 periods of ~5400 CVODE steps to settle to 1e-3. The returns y_j to the section
// M0 = level (crossed upwards, solvers/poincare_section.hpp) approach the cycle's point y* as
// y_j − y* ≈ Σ_i c_i μ_i^j v_i over the few multipliers that are not small; reduced rank extrapolation (RRE)
// [Smith1987] removes the k slowest from k + 2 returns: with Δ_j = y_{j+1} − y_j it takes the γ (Σ γ_j = 1) that
// minimise ‖Σ_j γ_j Δ_j‖ (a least-squares problem in k unknowns, GSL) and jumps to Σ_j γ_j y_{j+1}. On a linear
// map RRE is GMRES on (I − A)(y − y*) = 0, so the rounds converge like a restarted GMRES(k) on the return map:
// at the rate of the multipliers beyond the k-th, not of the first. A round whose jump is absurd (not finite, or
// beyond `largest_jump` times the round's own motion ‖y_{k+1} − y_0‖) is not taken: the run goes on from its last
// return, as plain iteration.
//
// The start, and each jump, is scaled onto the model's mass shell Σ x_i n_i = M (its initial mass): the returns are
// read at CVODE's steps, which keep the start's own mass (below atol 1e-10 only the outputs are projected onto the
// shell, solvers/cvode_integrator.hpp), and a start off the shell relaxes to the cycle of another mass (the Hopf
// normal form's point at 1 % below the curve carries 0.33 % more, brownian a = 0.95, graded K = 32).
//
// The norm is the densities' relative one, s_i = |y_i| + 1e-8 max |y| (as the shooting's scaling,
// solvers/limit_cycle.hpp): the far tail's tiny densities count by their own size and not by the noise floor.
// The result is a state on the cycle to `tolerance` in that norm, e.g. a start for a run that then settles in a
// few periods, or for shooting.
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "solvers/limit_cycle.hpp"
#include "solvers/model.hpp"

namespace aggkit {

struct CycleExtrapolation;

struct CycleExtrapolationOptions {
  int modes = 3;               // k: the slow multipliers removed a round (k + 2 returns a round), in [1, 8]
  int max_rounds = 6;          // in [1, 50]
  double tolerance = 1e-6;     // done where a round's jump is below this (relative, max over the classes)
  double largest_jump = 1e3;   // a jump beyond this many times the round's own motion is refused
  double rtol = 1e-6;          // CVODE's relative tolerance
  RunTolerance run;            // and its absolute tolerances
  long max_steps = 0;          // CVODE steps a round at most (0: the integrator's default)
  // Called after each round with the result so far (progress; may be empty).
  std::function<void(const CycleExtrapolation&)> on_round;
  void validate() const;       // throws InputError naming the option
};

struct CycleExtrapolation {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  bool converged = false;        // the last jump was below the tolerance
  std::vector<double> state;     // the last extrapolated point (on the section), else the last return
  double period = nan;           // the time between the last two returns
  double jump = nan;             // the last round's jump (relative), NaN where no round finished
  std::vector<double> jumps;     // every round's jump (0 where one was refused)
  int rounds = 0, returns = 0;   // rounds run, and returns to the section in all (the periods integrated)
  double seconds = 0;
  std::string note;              // how it ended
};

// From `start`, with the section M0 = `level` and a period near `period_guess` (crossings earlier than half of it
// in a round are not returns: the round may start on the section). Throws InputError for bad options, a start of
// the wrong length or a bad level or period guess; StepLimitReached where a round needs more than max_steps;
// other integration failures propagate.
CycleExtrapolation extrapolate_cycle(const AggregationModel& model, std::span<const double> start, double level,
                                     double period_guess, const CycleExtrapolationOptions& options = {});

}  // namespace aggkit

#pragma once
// The largest nontrivial Floquet multiplier of an attracting cycle estimated from its Poincaré return map by
// power iteration [Kuznetsov2004, Sec. 1.5]: a small perturbation δ of a state on the cycle, kept on the cycle's
// mass shell, is run on for a few returns to the section where M0 crosses its mid-range upwards. Near the cycle
// the return map is linear, P(x* + δ) − x* ≈ A δ, with the nontrivial Floquet multipliers as A's eigenvalues,
// so the j-th return deviates from the cycle as |μ_1|^j (μ_1 the largest) once the other multipliers' shares
// have decayed; the period of the j-th return, T_j, is a linear functional of that deviation and its distance
// from the cycle's period, d_j = |T_j − T*| / T*, falls by |μ_1| a return.
//
// Why not Arnoldi on the monodromy matrix (solvers/limit_cycle.hpp): far below the Hopf curve one period of the
// relaxation cycle costs 2000–14000 CVODE steps at rtol 1e-6 and tens of period maps at rtol 1e-10 are needed;
// a return-map estimate costs the few returns a perturbation takes to fall to the integration's floor (two to
// three periods where the cycle attracts strongly). What it gives up: the spectrum beyond μ_1, and precision
// where μ_1 is complex (the deviations then rotate and the ratio per return is |μ_1| only on average) or where
// the second multiplier is close to the first (its share decays as |μ_2/μ_1|^j).
//
// The estimate is the decay rate of the deviations fitted over the returns that lie above the floor
// (`resolved_factor` times the larger of `floor` and the cycle's own scatter); where only one return lies above it, the
// multiplier is bounded instead: |μ_1| ≲ resolved_factor · floor / d, an attraction too strong for the
// integration's noise to measure.
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "solvers/limit_cycle.hpp"
#include "solvers/model.hpp"

namespace aggkit {

struct ReturnMapOptions {
  // |δ_k| ≤ perturbation · n_k: pseudo-random signs and sizes, fixed seed. At 1e-2 the first returns of a cycle near
  // the curve (a = 0.75, λ = 3.16e-4) lay near the floor and the fit read 0.67; at 3e-2 and 1e-1 both read 0.13.
  double perturbation = 3e-2;
  int max_returns = 8;         // returns run at most (in [3, 50])
  double rtol = 1e-6;          // CVODE's relative tolerance (as the runs that found the cycle)
  RunTolerance tolerance;      // and its absolute tolerances
  long max_steps = 0;          // CVODE steps of the run at most (0: the integrator's default)
  // The relative changes of the period between returns that the integration resolves: at rtol 1e-6 on the
  // shipped scan's grid they kept falling geometrically down to 4e-7 (a = 0.75, λ = 1e-8 and 1e-9), at rtol 1e-8
  // on a coarse grid they scattered about 5e-8 once the perturbation had gone (tests/solvers/test_cycle_return_map.cpp).
  double floor = 1e-7;
  double resolved_factor = 3;  // a deviation counts where it exceeds this many floors
  void validate() const;       // throws InputError naming the option
};

// The cycle the state lies on: its period, M0's range (the section is M0 = (m0_min + m0_max) / 2, crossed
// upwards) and the relative scatter of its periods at the run's tolerances (e.g. the spread of the last periods
// of the run that found it), which raises the floor where it exceeds `floor`: the floor is the problem's, not
// only the tolerance's (rtol 1e-6 on the coarse grid K = 8, r = 1.6: the changes of an unperturbed cycle's period
// scatter by ~1e-5, and a floor of 1e-7 read that scatter as a multiplier 0.99; its spread 2.2e-5 there).
struct CycleReference {
  double period = 0, m0_min = 0, m0_max = 0, spread = 0;
};

struct ReturnMapMultiplier {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  double multiplier = nan;           // |μ_1|: the estimate, or the bound where `bounded`
  double multiplier_error = nan;     // its standard error from the fit's scatter (three or more returns)
  bool bounded = false;              // only an upper bound: the second return already lay within the floor
  std::vector<double> deviations;    // d_j, one per return run
  double floor = nan;                // the relative floor the deviations were measured against
  double seconds = 0;
  std::string note;                  // how it was measured, or why there is no estimate
  bool found() const { return std::isfinite(multiplier); }
};

// The perturbed state: δ_k = ε n_k ξ_k (ξ_k uniform in [-1, 1], a fixed seed), less c x_k n_k so that the mass
// Σ x_k δ_k is 0 (the mass direction's multiplier is the trivial 1 of a conserved quantity); never negative.
std::vector<double> mass_keeping_perturbation(std::span<const double> on_cycle, std::span<const double> sizes, double epsilon);

// The estimate from the deviations d_j (relative changes of the period from one return to the next), as
// return_map_multiplier makes it with `resolved` = resolved_factor · floor: d_0, over the first return, still carries
// the fast multipliers' share of the perturbation and is left out of the fit; over the deviations from d_1 on that
// exceed `resolved`, the last four are fitted by weighted least squares (GSL; weights (d_j / resolved)², as ln d_j
// is uncertain by the floor over d_j) to ln d_j = α + j ln|μ_1|, the slope's standard error giving the estimate's. Where fewer than two exceed it, or where their fit rises although the next return fell
// within the floor (noise next to the floor), the last deviation d above the floor bounds it instead, |μ_1| ≤
// resolved / d < 1; where even d_0 lies within the floor there is no estimate. Sets multiplier, multiplier_error,
// bounded and note.
void estimate_multiplier(const std::vector<double>& deviations, double resolved, ReturnMapMultiplier& result);

// Throws InputError for bad options, a reference that is not a cycle (period ≤ 0, m0_max ≤ m0_min) or a state of
// the wrong length; integration failures propagate (StepLimitReached where max_steps runs out).
ReturnMapMultiplier return_map_multiplier(const AggregationModel& model, std::span<const double> on_cycle,
                                          const CycleReference& reference, const ReturnMapOptions& options = {});

}  // namespace aggkit

#pragma once
// Periodic orbits of the aggregation-shattering equations computed directly: single shooting on the period
// map φ_T (CVODE inside, solvers/cvode_integrator.hpp) with matrix-free Newton–Krylov and a Poincaré phase
// condition; Floquet multipliers as the eigenvalues of the monodromy matrix [Doedel2007].
//
// Why shooting rather than collocation: the system is stiff (loss rates from ~1 at the monomers to ~1e-9 in the
// giant clusters) and its periods reach 10^3..10^9; collocation would need a mesh over one period for each of
// the few hundred classes, with mesh adaptation through the relaxation bursts, while shooting lets CVODE's BDF
// choose its own steps, and each Krylov vector costs one integration over a period. Dissipation makes almost
// every Floquet multiplier tiny, so GMRES on (M − I) converges in about as many iterations as there are
// multipliers not near 0 (a few tens).
//
// The equations, unknowns (x0, T) with x0 on the model's size classes:
//   rows k ≠ m:  (φ_T(x0) − x0)_k = 0          (periodicity)
//   row m:       Σ_k x_k x0_k − M = 0           (mass: the flow keeps it, so one periodicity row is redundant;
//                                               m is the mass row of solvers/mass_constrained_system.hpp)
//   phase:       f(x_ref) · (x0 − x_ref) = 0    (a Poincaré section through the start x_ref)
// scaled by s_k = |x_ref,k| + 1e-8 max|x_ref| (relative errors of the densities that carry the dynamics); the
// unknowns move on d_k = min(s_k, 2 |x_ref,k|) (the far tail in proportion to itself). J·v is a forward
// difference of φ_T along d∘v (relative perturbation 1e-5; CVODE at rtol 1e-10 keeps its noise near 1e-5) plus
// f(φ_T(x0)) ∂T, on the same scale as Newton's steps; GMRES is PETSc's KSP [Balay2022] on a MatShell.
//
// Floquet multipliers: Arnoldi (Spectra) on the monodromy matrix ∂φ_T/∂x0, applied by the same differences, on
// the perturbations that keep the mass (the mass direction's multiplier 1 is removed exactly: its perturbation
// is projected out). The phase direction f(x0) keeps the other trivial multiplier 1, recognised by its
// eigenvector; the cycle is stable when every other multiplier has |μ| < 1.
#include <array>
#include <complex>
#include <cstddef>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "solvers/model.hpp"

namespace aggkit {

struct IntegratorOptions;  // solvers/cvode_integrator.hpp

struct LimitCycleOptions {
  double rtol = 1e-10;               // CVODE's relative tolerance of every period map
  double tolerance = 1e-5;           // Newton stops at max_k |F_k| ≤ tolerance (the scaled residual above)
  int max_newton_iterations = 30;
  double linear_tolerance = 1e-3;    // relative GMRES tolerance of each Newton step
  int max_krylov_iterations = 80;    // per Newton step
  int floquet_count = 4;             // nontrivial multipliers reported (largest |μ| first)
  std::size_t orbit_samples = 200;   // points of the one-period orbit output
  void validate() const;             // throws InputError naming the option
};

struct LimitCycle {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  bool converged = false;
  double period = nan;
  std::vector<double> state;                      // x0: a point of the cycle on the model's classes
  std::vector<double> sizes;                      // those classes' sizes
  double m0_min = nan, m0_max = nan;              // the amplitude of M0 over one period
  std::vector<std::complex<double>> floquet;      // nontrivial multipliers, |μ| descending
  bool floquet_converged = false;
  bool stable = false;                            // converged, and every nontrivial |μ| < 1
  std::vector<double> orbit_time;                 // one period, orbit_samples + 1 points from 0 to T
  std::vector<std::array<double, 4>> orbit_moments;  // M0..M3 there
  int newton_iterations = 0;
  long krylov_iterations = 0;
  long period_maps = 0;                           // CVODE integrations over a period
  double residual = nan;                          // the final scaled residual
  double seconds = 0;
  std::string note;                               // why it did not converge
};

// The periodic orbit through (near) `start` with period near `period_guess`. λ must be constant. Throws
// InputError for bad options, a start of the wrong length or a bad period guess.
LimitCycle find_limit_cycle(const AggregationModel& model, std::span<const double> start, double period_guess,
                            const LimitCycleOptions& options = {});

// A start for find_limit_cycle from the model's own run: the state at the last upward crossing of M0 through
// its mean over the second half of [0, t_end] (outputs every `spacing`), and the mean spacing of the last
// crossings as the period. nullopt where the run's second half shows fewer than three crossings, or none among its
// last 4000 outputs (states further back are not kept). The run starts from the model's initial state, or
// from `from` (one density per class) where given.
struct CycleStart {
  std::vector<double> state;
  double period = 0;
  int crossings = 0;
  std::vector<double> times, m0;  // the run's second half: M0 at each output, whose crossings these are
  // M0 over the second half at the internal steps: where a relaxation burst is narrower than the outputs'
  // spacing, the steps (whose size the burst bounds) resolve its peak (analysis/crossing_periods.hpp,
  // cycle_settling with times). Not merged with the outputs: those are projected onto the mass shell and the
  // steps not, and M0's tiny offset between the two made samples a fraction of a step apart zigzag across the
  // mid-range (a smooth cycle of period 71.6 read as "unsettled", mean period 1.3).
  std::vector<double> step_times, step_m0;
};
// The absolute tolerances of such a run: IntegratorOptions' atol, atol_floor and atol_mass (0: their defaults).
struct RunTolerance {
  double atol = 0.0, atol_floor = 0.0, atol_mass = 0.0;
};
// The integrator's options of a run at `rtol` with these tolerances and at most `max_steps` CVODE steps (0: the
// integrator's default). Throws InputError for max_steps < 0 (the tolerances' ranges are checked by integrate).
IntegratorOptions cycle_run_options(double rtol, long max_steps, const RunTolerance& tolerance);
// `max_steps` bounds the run's CVODE steps (0: the integrator's default); a run that needs more throws
// StepLimitReached (solvers/cvode_integrator.hpp) naming the step count and the time reached. `grid_end`, where
// given, receives what the run shows of the grid's end, whether or not it oscillates (up to where it stopped, where
// it throws).
struct GridEnd {
  double leaked_mass = 0.0;  // the mass the run lost through the truncation (drop) by t_end
  // The most mass Σ x_k n_k held at an output by the classes whose pivots exceed N/2 (the grid's top octave):
  // a cycle whose quiescent phase grows clusters to sizes ~N fills them before it leaks.
  double top_octave_mass = 0.0;
};
std::optional<CycleStart> cycle_start_from_run(const AggregationModel& model, double t_end, double spacing,
                                               double rtol = 1e-8, std::span<const double> from = {},
                                               long max_steps = 0, const RunTolerance& tolerance = {},
                                               GridEnd* grid_end = nullptr);

}  // namespace aggkit

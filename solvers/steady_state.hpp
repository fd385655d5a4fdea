#pragma once
// Steady states of the truncated aggregation-shattering system by PETSc SNES Newton–Krylov [Balay2022] on
// the mass-constrained equations (solvers/mass_constrained_system.hpp): F_k = f_k (k < N), F_N = Σ k n_k - M.
// J·v is the exact bilinear form of the fast O(N R log N) rates (a MatShell, no differencing); GMRES is
// right-preconditioned by the monomer-attachment lower-triangular part of J_F (O(N) per application);
// backtracking line search; Eisenstat–Walker forcing terms [Eisenstat1996] (the first one tightened to
// about tolerance / residual when the start is within 4 orders of the tolerance: one accurate step then
// replaces several loose ones). Without an initial guess the
// start is the state of a short CVODE run from the model's initial state (retried with a longer run if
// Newton fails or lands on a root with negative densities). Natural-parameter continuation in λ or in the
// brownian exponent a reuses (secant-extrapolates) the previous solutions.
//
// What the steady state means under truncation: under `cutoff` (mass conserved exactly) it is the exact
// steady state of the truncated system. Under `drop` every size below N is stationary and the largest
// class drains at the leak rate / N; `leak_rate` reports the mass flux out of the truncation relative to
// M, i.e. how far the truncated system is from a true steady state (a well-chosen N makes it tiny).
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "solvers/model.hpp"
#include "solvers/rates.hpp"

namespace aggkit {

struct SteadyStateOptions {
  // Convergence: ||F(n)||_2 ≤ relative_tolerance · ||F(n(0))||_2 (n(0) the model's initial state, so the
  // scale is the rate of the problem and does not depend on how good the start is), and the root balances
  // its own rates: the free rows' residual ≤ balance_tolerance · ||(∂f_k/∂n_k n_k)||_2 and the mass row's
  // ≤ balance_tolerance · M. The second test rules at small densities (small λ), where the first alone
  // accepted roots with M0 5 % off. Where Newton stagnates (the round-off floor) the balance measured
  // 1e-14 … 5e-8 (brownian a = 0.59, graded grid to sizes 1e12), hence 1e-6; λ_crit then moves by < 1e-5.
  double relative_tolerance = 1e-10;
  double balance_tolerance = 1e-6;
  int max_newton_iterations = 50;
  RatesPath rates = RatesPath::fast;
  double lowrank_tolerance = 1e-12;  // kernels without an exact factorisation (ballistic)
  bool precondition = true;          // false: plain GMRES (for comparison only)
  bool eisenstat_walker = true;      // adaptive GMRES tolerances; false: linear_tolerance fixed
  double linear_tolerance = 1e-4;    // relative GMRES tolerance when eisenstat_walker is false
  int krylov_restart = 100;
  int max_krylov_iterations = 2000;  // per Newton step
  // Start without a guess: CVODE (rtol start_rtol) from n(0) to start_time, then up to `start_retries`
  // retries each integrating 10x longer.
  double start_time = 20.0;
  double start_rtol = 1e-4;
  int start_retries = 2;
  // Coarse-to-fine start (without a guess, when N > coarse_start_above and the initial state lies within
  // the first N / 4 sizes): the steady state at N / 4 (found the same way, recursively, down to a CVODE
  // start at N ≤ coarse_start_above), kept up to N / 8 and beyond replaced by a fit
  // ln n_k = a + b ln k + c k over N / 32 ... N / 8, extended to N. Newton then solves the size-N system
  // to the same tolerance, so the result does not depend on the start; the start saves the CVODE run at
  // full size and most of Newton's damped steps. If Newton fails from it, the CVODE start follows.
  // 0 disables.
  std::size_t coarse_start_above = 4096;
  // PETSc options-database entries for the SNES and its KSP/PC ("-snes_rtol 1e-12 -ksp_type bcgs"),
  // applied after the settings above (they override them), then those of the command line
  // (`aggkit run ... -- OPTIONS`, not an engine option). Both belong to this solve alone: each solve reads
  // them from a database of its own (solvers/petsc_database.hpp), as PETSc's per-object options do, so
  // solves at the same time never see each other's.
  std::string petsc_options;
  std::string command_line_petsc_options;
  void validate() const;  // throws InputError
};

struct SteadyStateResult {
  std::vector<double> n;                 // n_1..n_N at the steady state
  bool converged = false;
  int newton_iterations = 0;
  long krylov_iterations = 0;
  double relative_residual = 0;          // final ||F|| / ||F(n(0))||
  std::vector<double> residual_history;  // per Newton iteration (the first entry: the start)
  double seconds = 0;
  // Added beyond the shared interface:
  double leak_rate = 0;                  // mass per unit time leaving through N, relative to M (drop)
  double most_negative_density = 0;      // min(0, min_k n_k) relative to max_k n_k
  double negative_mass_fraction = 0;     // Σ x_k max(0, -n_k) / Σ x_k |n_k| (x_k: the sizes of the entries)
  double start_time = 0;                 // CVODE time of the start (0: the caller's guess or a coarse start)
  std::size_t coarse_size = 0;           // size of the coarse steady state the start came from (0: none)
  double start_seconds = 0;              // wall time spent finding the start (CVODE or the coarse solve)
  double setup_seconds = 0;              // wall time building the size-N system (kernel factorisation)
  std::string note;                      // why it did not converge, retries
  std::vector<std::string> unused_petsc_options;  // PETSc options no solver object read (misspelled?)
};

// Steady state of model (a serial, PETSC_COMM_SELF solve: each MPI rank solves its own points).
// λ must be constant in time. Throws InputError on bad options or model.
SteadyStateResult solve_steady_state(const AggregationModel& model, const SteadyStateOptions& options = {},
                                     std::span<const double> initial_guess = {});

// Σ x_k max(0, -n_k) / Σ x_k |n_k|: the share of the mass in negative entries (x_k: the sizes of the
// entries, the pivots on a graded grid). solve_steady_state refuses a root where it exceeds 1e-6, as well
// as one with min n / max n < -1e-8: on a graded grid a tail of giant clusters at 1e-15 of the largest
// density can hold most of the mass, so a tail gone negative passes the density test yet changes the
// dynamics.
double negative_mass_fraction(std::span<const double> n, std::span<const double> sizes);

// Natural-parameter continuation: the steady states of `base` with λ = lambdas[i] (in the given order),
// each started from the secant extrapolation of the previous two solutions (the first from CVODE).
std::vector<SteadyStateResult> continue_in_lambda(const AggregationModel& base, std::span<const double> lambdas,
                                                  const SteadyStateOptions& options = {});
// The same along the exponent a of the brownian kernel (i/j)^a + (j/i)^a.
std::vector<SteadyStateResult> continue_in_a(const AggregationModel& base, std::span<const double> a_values,
                                             const SteadyStateOptions& options = {});

}  // namespace aggkit

#pragma once
// Linear stability of a steady state (solvers/steady_state.hpp): the rightmost eigenvalues of the
// Jacobian ∂f/∂n on the mass shell, i.e. the finite eigenvalues of the pencil (J_F, B) of
// solvers/mass_constrained_system.hpp. Eliminating the constrained components (v_m = -Σ_{k<m} (k+1) v_k
// /(m+1) on the mass row m, pinned components 0) leaves the standard problem A u = μ u,
// A = J_{<m,<m} + J_{<m,m} t^T with t_k = -(k+1)/(m+1): the trivial mass-conservation mode is gone.
//   dense:  A formed from the direct Jacobian, all eigenvalues by Eigen (small N);
//   dense-shift-invert (graded grids, solvers/size_grid.hpp): Arnoldi on (A - σI)^{-1} by one dense LU;
//   krylov: Arnoldi (Spectra) on the shift-invert operator (A - σI)^{-1}, each application one GMRES
//           solve of (J_F - σB) v = (b, 0) with the monomer-attachment preconditioner (PETSc KSP). The
//           eigenvalues nearest σ come out first; the rightmost are then selected from those, which is
//           right when the rightmost eigenvalues are also the ones nearest σ (the oscillatory pair of
//           the aggregation-shattering problem is slow: |μ| ≪ the fast loss rates ~ c_k).
// locate_hopf finds λ_crit(a) where the rightmost complex pair crosses Re μ = 0 ([Kalinov2022, Sec. 5.2]
// and [Brilliantov2018]: sustained oscillations for 1/2 < a ≤ 1 and 0 < λ < λ_crit(a)). Eigensolvers:
// [Spectra], [Balay2022].
#include <complex>
#include <span>
#include <string>
#include <vector>

#include "solvers/model.hpp"
#include "solvers/steady_state.hpp"

namespace aggkit {

enum class SpectrumMethod { automatic, dense, krylov };

struct StabilityOptions {
  SpectrumMethod method = SpectrumMethod::automatic;
  std::size_t dense_limit = 800;      // automatic: dense up to this N, Krylov above
  double shift = 0.0;                 // σ of the shift-invert Krylov path
  int krylov_eigenvalues = 16;        // how many eigenvalues nearest σ Arnoldi computes (≥ count)
  double eigen_tolerance = 1e-10;     // Spectra's relative tolerance on the Ritz values of (A - σI)^{-1}
  double linear_tolerance = 1e-12;    // relative GMRES tolerance of each shift-invert solve
  int krylov_restart = 100;           // GMRES restart length of the shift-invert solves
  double lowrank_tolerance = 1e-12;   // kernels without an exact factorisation
};

struct StabilityResult {
  std::vector<std::complex<double>> rightmost;  // rightmost eigenvalues, real part descending
                                                // (the trivial mass-conservation mode excluded)
  bool stable = true;                            // Re(rightmost[0]) < 0
  // Added beyond the shared interface:
  std::string method;                            // "dense", "krylov" or "dense-shift-invert" (graded grid)
  long linear_iterations = 0;                    // GMRES iterations of the shift-invert solves (krylov)
  int operator_applications = 0;                 // shift-invert solves (krylov)
  double seconds = 0;
};

StabilityResult analyse_stability(const AggregationModel& model, std::span<const double> steady_state,
                                  int count = 6);
StabilityResult analyse_stability(const AggregationModel& model, std::span<const double> steady_state, int count,
                                  const StabilityOptions& options);

// The rightmost complex pair (Im > 0 member) among `eigenvalues`; {NaN, NaN} if there is none.
std::complex<double> rightmost_complex_pair(std::span<const std::complex<double>> eigenvalues);

struct HopfPoint {
  double a = 0;
  bool found = false;            // false: no crossing in [lambda_lo, lambda_hi] (note says which side)
  double lambda_crit = 0;        // the rightmost complex pair crosses Re = 0 here
  double lambda_tolerance = 0;   // |lambda_crit - true crossing| bound of the root bracket
  double omega = 0;              // Im of the crossing pair: oscillation period 2π/ω
  std::string note;
  // Added beyond the shared interface:
  int evaluations = 0;           // steady state + spectrum computations
  double seconds = 0;
  double cpu_seconds = 0;        // process CPU time (the machine may be shared)
  std::vector<double> steady_state;  // the steady state at the final bracket's stable end (found only)
  std::vector<double> steady_sizes;  // its classes' sizes on a graded grid (empty: 1..N)
  double steady_lambda = 0;          // the λ of steady_state
  // Where the search ran out of positive steady states (not found): the λ without one, and the smallest λ
  // evaluated with one (0: none). A larger N, or λ_crit < lambda_lowest_steady.
  double lambda_no_steady = 0;
  double lambda_lowest_steady = 0;
};

struct HopfOptions {
  SteadyStateOptions steady;
  StabilityOptions stability;
  // A steady state at a nearby (a, λ), of any size: the first Newton guess (cut to N, or extended to N
  // by extend_steady_state). Empty: the steady-state solver's own start.
  std::vector<double> start;
  std::vector<double> start_sizes;  // the sizes of start's classes (empty: 1..start.size())
  // Where `start` is a steady state: (start_a, start_lambda); start_lambda = 0: not known. When known, the
  // first steady state is reached from `start` by continuation along the line from (start_a, ln start_lambda)
  // to (a, ln λ) in steps of at most 0.002 in a and 0.5 in ln λ, each Newton solve starting from the last
  // one, so that it stays on start's branch (the truncated system has other positive roots: from a CVODE
  // start at brownian a = 0.6, λ = 5.745e-8, K = 64, r = 1.04, N = 2^33 Newton finds a saddle with a positive
  // real eigenvalue and M0 20 % above the branch that carries the Hopf point). A failed path means no positive
  // root on the branch at that λ (no CVODE start is tried); later evaluations follow the nearest evaluated
  // λ the same way (steps ≤ 0.5 in ln λ).
  double start_a = 0;
  double start_lambda = 0;
  // When [lambda_lo, lambda_hi] does not hold the crossing, step the bracket towards it (each step
  // moves it by its own width in ln λ, the known end becoming the new inner end) up to this many times.
  int bracket_steps = 0;
};

// λ_crit for the brownian kernel (i/j)^a + (j/i)^a with the other settings of `base` (size N,
// truncation, initial mass). Sustained oscillations for λ < λ_crit. The growth rate g(λ) = Re μ of the
// rightmost complex pair is bracketed on [lambda_lo, lambda_hi] (moved up to options.bracket_steps
// times if it does not hold the crossing) and the root is found by Brent's method in ln λ
// (gsl_root_fsolver_brent; solvers/hopf.cpp) until the bracket is narrower than relative_tolerance · λ; each steady state
// starts from the nearest one already found (continuation in λ), the first from options.start if
// given. Throws InputError for a ∉ [0, 1] or a bad λ range. If no steady state exists at the lower end
// (too short a truncation for that λ), found = false and the note says so.
HopfPoint locate_hopf(const AggregationModel& base, double a, double lambda_lo, double lambda_hi,
                      double relative_tolerance = 1e-3);
HopfPoint locate_hopf(const AggregationModel& base, double a, double lambda_lo, double lambda_hi,
                      double relative_tolerance, const HopfOptions& options);

}  // namespace aggkit

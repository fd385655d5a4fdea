#pragma once
// λ_crit(a) converged in the truncation N, and the curve λ_crit(a) by continuation in a.
//
// Why N must grow as λ falls: for a > 1/2 and small λ a large cluster grows mostly by taking up monomers
// and small clusters (K_kj ≈ (k/j)^a for j ≪ k) and is shattered at λ times its collision rate, so the
// steady-state tail obeys the drift–loss balance d/dk (A k^a n_k) = -λ B k^a n_k with A = Σ j^{1-a} n_j,
// B = Σ j^{-a} n_j, i.e. n_k ∝ k^{-a} e^{-c k} with c = λ B / A (model of [Kalinov2022, eq. 4]; the
// balance is derived in bench/results/log/lambda-crit-curve.md, where c ≈ 0.62 λ … 0.67 λ is measured near
// λ_crit at a = 0.75 and 0.8). A truncation at N cuts the tail where it has fallen by e^{-cN}, so N must
// grow like 1/λ; below c N ≈ 4 … 5 the quasi-steady state of the truncated system has no positive root.
//
// locate_hopf_converged finds λ_crit at N and at 2N (doubling further while the relative change exceeds
// `convergence`): the value reported is the one at the largest N, with |λ(2N) - λ(N)| as its
// truncation error bar (an upper bound when the convergence is geometric, as it is with an exponential
// tail: each doubling multiplies the truncation error by e^{-cN}). The 2N search starts from the N
// result: a bracket of ±convergence around λ(N) whose ends have opposite growth rates already shows the
// change is within the tolerance, and the N steady state (extended) starts Newton.
//
// hopf_curve walks a list of a values (from the top, a = 1, downwards: λ_crit falls steeply towards
// a = 1/2), guessing each λ_crit by extrapolating ln λ_crit linearly in a from the two previous points and
// starting at N = size_per_inverse_lambda / λ_guess (N ∝ 1/λ), so no a starts with a blind bracket or an
// N too short for a steady state (an N that is, all the same, is doubled). Spectra as in locate_hopf
// ([Kalinov2022, Sec. 5.2]).
#include <cstddef>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "solvers/stability.hpp"

namespace aggkit {

struct HopfCurveOptions {
  // Steady-state and spectrum settings (start and bracket_steps are set by the search). The shift-invert
  // solves are looser than analyse_stability's defaults: Ritz values to 1e-8 and GMRES to 1e-9 move
  // Re μ of the pair by ~2e-10 at a = 0.75, N = 8192 (measured against 1e-10 / 1e-12), far below the
  // growth rates that decide a bracket (|dRe μ/d ln λ| ~ 1e-4 … 1e-3: a shift of ~1e-6 in λ relative),
  // and save ~40 % of the GMRES iterations.
  HopfOptions hopf = [] {
    HopfOptions h;
    h.stability.eigen_tolerance = 1e-8;
    h.stability.linear_tolerance = 1e-9;
    h.stability.krylov_eigenvalues = 6;
    return h;
  }();
  double relative_tolerance = 1e-3;  // bracket of each λ_crit(N), relative
  double convergence = 0.01;         // accepted |λ(2N) - λ(N)| / λ(2N)
  double bracket = 0.05;             // half-width (relative) of the first bracket around a guess
  int bracket_steps = 12;            // how far a bracket may be stepped towards the crossing
  // Largest N tried (memory and time); 0: 2^16 on the uniform grid, 2^60 on a graded one (whose unknowns
  // grow only by ln 2 / ln r per doubling).
  std::size_t max_size = 0;
  std::size_t effective_max_size(const SizeGrid& grid) const {
    return max_size ? max_size : grid.uniform() ? std::size_t(1) << 16 : std::size_t(1) << 60;
  }
  // Smallest N for a given λ guess: N ≥ size_per_inverse_lambda / λ (rounded up to a power of two),
  // i.e. c N ≥ ~5 with c ≈ 0.65 λ (the doubled N then has c N ≥ 10, where λ_crit moves by ~1e-4
  // relative per doubling, measured at a = 0.75 and 0.8); and never below min_size.
  double size_per_inverse_lambda = 8.0;
  std::size_t min_size = 512;
  // d ln λ_crit / da for the second point's guess, before two converged points give a slope (0: none, the
  // guess is then the first point's λ_crit).
  double log_slope = 0.0;
  void validate() const;  // throws InputError
};

struct ConvergedHopfPoint {
  double a = 0;
  bool converged = false;      // λ_crit(size) within `convergence` of λ_crit(size / 2)
  double lambda_crit = 0;      // at the largest N that found it
  double omega = 0;
  std::size_t size = 0;        // that N
  double lambda_crit_half = 0; // at size / 2 (0 if not found)
  double change = 0;           // |λ(size) - λ(size/2)| / λ(size): the truncation error bar, relative
  double bracket = 0;          // Brent's bracket width at `size` (absolute)
  std::vector<HopfPoint> by_size;  // every locate_hopf call, in order (a, N, λ_crit, note)
  std::vector<std::size_t> sizes;  // the N of each entry of by_size
  // Graded grid (solvers/size_grid.hpp): λ_crit at the final N repeated with the resolved block doubled
  // (2K) and with r - 1 halved; the changes relative to λ_crit are error bars like `change`, and
  // `converged` needs all three within the tolerance. NaN on the uniform grid.
  std::size_t resolved = 0;    // K of the reported value (0: uniform grid)
  double ratio = 1.0;          // r of the reported value
  std::size_t unknowns = 0;    // size classes at the reported N
  double lambda_crit_2K = std::numeric_limits<double>::quiet_NaN();
  double change_K = std::numeric_limits<double>::quiet_NaN();
  double lambda_crit_fine_ratio = std::numeric_limits<double>::quiet_NaN();
  double change_ratio = std::numeric_limits<double>::quiet_NaN();
  int evaluations = 0;
  double seconds = 0, cpu_seconds = 0;
  std::string note;
};

// λ_crit(a) of `base` (its kernel replaced by brownian(a)) converged in N, starting from λ ≈ lambda_guess
// and N = size (or larger, from options.size_per_inverse_lambda). `start`: a steady state near (a, λ_guess)
// of any size (may be empty), solved at (start_a, start_lambda) if start_lambda > 0: the first steady state is
// then reached by continuation from it (HopfOptions), and so is each later N's from the last N's. Throws
// InputError on bad options.
ConvergedHopfPoint locate_hopf_converged(const AggregationModel& base, double a, double lambda_guess, std::size_t size,
                                         const HopfCurveOptions& options = {}, std::span<const double> start = {},
                                         std::span<const double> start_sizes = {}, double start_a = 0,
                                         double start_lambda = 0);

// The curve over a_values (in the given order; start at the largest a), the first point from
// lambda_guess and size. A point that does not converge stops the continuation's extrapolation from it
// (the next guess uses the last converged points). on_point, if given, is called as each point finishes.
std::vector<ConvergedHopfPoint> hopf_curve(const AggregationModel& base, std::span<const double> a_values,
                                           double lambda_guess, std::size_t size, const HopfCurveOptions& options = {},
                                           const std::function<void(const ConvergedHopfPoint&)>& on_point = {});

}  // namespace aggkit

#pragma once
// A logistic step fitted by nonlinear least squares with standard errors, through GSL
// (gsl_multifit_nlinear, Levenberg–Marquardt with a trust region):
//   y(x) = low + (high − low) / (1 + exp((x − midpoint)/width)),
// a fall from `high` to `low` around `midpoint` when width > 0 (a rise when width < 0). Used for C/N_tot
// against log10 γ_n of the DEM campaign [Trivino2025, Fig. 4]. The points are taken as independent with
// equal variance, estimated from the residuals, s² = Σ r²/(n − 4): the standard errors are the square roots
// of the diagonal of s² (JᵀJ)⁻¹ at the solution.
#include <cstddef>
#include <limits>
#include <span>

namespace aggkit {

struct LogisticFit {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  double high = nan, low = nan, midpoint = nan, width = nan;
  double high_error = nan, low_error = nan, midpoint_error = nan, width_error = nan;
  double residual_sum_of_squares = nan;
  std::size_t points = 0;
  // The solver met its tolerances and the parameters are determined: finite errors, the midpoint's below the
  // range of x. A step falling between two abscissae often leaves JᵀJ singular (then this is false); when it
  // does not, the small error of its midpoint is still only where the data have no points: check that some
  // points lie inside midpoint ± 2 |width|.
  bool converged = false;
  double operator()(double x) const;
};

// x and y of the same length (else InputError, key "fit"); fewer than 5 points, or non-finite values, give an
// unconverged fit with NaN parameters.
LogisticFit fit_logistic(std::span<const double> x, std::span<const double> y);

}  // namespace aggkit

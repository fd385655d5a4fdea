#pragma once
// Straight-line least squares y = c0 + c1 x with standard errors, through GSL (gsl_fit_linear): the
// envelope and relaxation rates of analysis/oscillation.cpp. The points are taken as independent with equal variance; the
// variance is estimated from the scatter about the line, s² = Σ r² / (n - 2), so that
// se(c1) = sqrt(s² / Σ (x - x̄)²) and se(c0) = sqrt(s² (1/n + x̄² / Σ (x - x̄)²)).
#include <cstddef>
#include <limits>
#include <span>

namespace aggkit {

struct LineFit {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  double intercept = nan, slope = nan;
  // Standard errors; 0 for an exact fit through 2 points (no scatter to estimate the variance from).
  double intercept_error = nan, slope_error = nan;
  double residual_sum_of_squares = nan;  // Σ (y - c0 - c1 x)²
  std::size_t points = 0;
  // False with fewer than 2 points or all x equal (the slope is undefined): every field but `points`
  // is then NaN.
  bool valid() const { return points >= 2 && slope == slope; }
};

// x and y of the same length (else InputError, key "fit"); non-finite values are not checked here.
LineFit fit_line(std::span<const double> x, std::span<const double> y);

}  // namespace aggkit

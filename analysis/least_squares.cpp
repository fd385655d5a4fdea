#include "analysis/least_squares.hpp"

#include <gsl/gsl_fit.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "analysis/input_error.hpp"

namespace aggkit {

LineFit fit_line(std::span<const double> x, std::span<const double> y) {
  if (x.size() != y.size())
    throw InputError("fit", std::to_string(y.size()) + " values", "as many as abscissae (" + std::to_string(x.size()) + ")");
  LineFit fit;
  fit.points = x.size();
  if (x.size() < 2) return fit;
  // All x equal: Σ (x - x̄)² = 0 and gsl_fit_linear would divide by it.
  if (std::all_of(x.begin(), x.end(), [&](double v) { return v == x.front(); })) return fit;
  double cov00 = 0, cov01 = 0, cov11 = 0;
  gsl_fit_linear(x.data(), 1, y.data(), 1, x.size(), &fit.intercept, &fit.slope, &cov00, &cov01, &cov11,
                 &fit.residual_sum_of_squares);
  if (x.size() == 2) {  // s² = Σ r² / 0: two points fix the line and leave no scatter
    fit.intercept_error = fit.slope_error = 0.0;
  } else {
    fit.intercept_error = std::sqrt(cov00);
    fit.slope_error = std::sqrt(cov11);
  }
  return fit;
}

}  // namespace aggkit

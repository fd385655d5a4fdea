#include "analysis/logistic_fit.hpp"

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <gsl/gsl_vector.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "analysis/input_error.hpp"

namespace aggkit {

namespace {

struct Data {
  std::span<const double> x, y;
};

// Parameters p = (high, low, midpoint, width).
double model(const gsl_vector* p, double x) {
  const double high = gsl_vector_get(p, 0), low = gsl_vector_get(p, 1);
  const double mid = gsl_vector_get(p, 2), width = gsl_vector_get(p, 3);
  return low + (high - low) / (1 + std::exp((x - mid) / width));
}

int residuals(const gsl_vector* p, void* data, gsl_vector* f) {
  const Data& d = *static_cast<const Data*>(data);
  for (std::size_t i = 0; i < d.x.size(); ++i) gsl_vector_set(f, i, model(p, d.x[i]) - d.y[i]);
  return GSL_SUCCESS;
}

int jacobian(const gsl_vector* p, void* data, gsl_matrix* J) {
  const Data& d = *static_cast<const Data*>(data);
  const double high = gsl_vector_get(p, 0), low = gsl_vector_get(p, 1);
  const double mid = gsl_vector_get(p, 2), width = gsl_vector_get(p, 3);
  for (std::size_t i = 0; i < d.x.size(); ++i) {
    const double z = (d.x[i] - mid) / width;
    // s = 1/(1 + e^z); ds/dz = −s(1 − s), computed without overflow for large |z|.
    const double s = z > 0 ? std::exp(-z) / (1 + std::exp(-z)) : 1 / (1 + std::exp(z));
    const double ds = -s * (1 - s);
    gsl_matrix_set(J, i, 0, s);
    gsl_matrix_set(J, i, 1, 1 - s);
    gsl_matrix_set(J, i, 2, (high - low) * ds * (-1 / width));
    gsl_matrix_set(J, i, 3, (high - low) * ds * (-z / width));
  }
  return GSL_SUCCESS;
}

}  // namespace

double LogisticFit::operator()(double x) const { return low + (high - low) / (1 + std::exp((x - midpoint) / width)); }

LogisticFit fit_logistic(std::span<const double> x, std::span<const double> y) {
  if (x.size() != y.size())
    throw InputError("fit", std::to_string(y.size()) + " values", "as many as abscissae (" + std::to_string(x.size()) + ")");
  LogisticFit fit;
  fit.points = x.size();
  const std::size_t n = x.size(), parameters = 4;
  if (n < parameters + 1) return fit;
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) return fit;
  const auto [x_min, x_max] = std::minmax_element(x.begin(), x.end());
  if (*x_max == *x_min) return fit;

  // Start: the plateaus from the ends of the x range, the midpoint where y is nearest their mean, width a
  // tenth of the range (sign from which end is higher).
  std::size_t first = 0, last = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (x[i] < x[first]) first = i;
    if (x[i] > x[last]) last = i;
  }
  const double y_first = y[first], y_last = y[last];
  const double middle = 0.5 * (y_first + y_last);
  std::size_t nearest = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (std::abs(y[i] - middle) < std::abs(y[nearest] - middle)) nearest = i;
  const double start[] = {y_first, y_last, x[nearest], (*x_max - *x_min) / 10};

  Data data{x, y};
  gsl_multifit_nlinear_fdf fdf;
  fdf.f = residuals;
  fdf.df = jacobian;
  fdf.fvv = nullptr;
  fdf.n = n;
  fdf.p = parameters;
  fdf.params = &data;
  gsl_multifit_nlinear_parameters settings = gsl_multifit_nlinear_default_parameters();
  gsl_multifit_nlinear_workspace* work = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &settings, n, parameters);
  gsl_vector_const_view p0 = gsl_vector_const_view_array(start, parameters);
  gsl_multifit_nlinear_init(&p0.vector, &fdf, work);
  int info = 0;
  gsl_error_handler_t* previous = gsl_set_error_handler_off();
  const int status = gsl_multifit_nlinear_driver(200, 1e-10, 1e-10, 1e-12, nullptr, nullptr, &info, work);
  const gsl_vector* p = gsl_multifit_nlinear_position(work);
  const gsl_vector* f = gsl_multifit_nlinear_residual(work);
  double chi2 = 0;
  gsl_blas_ddot(f, f, &chi2);
  gsl_matrix* covariance = gsl_matrix_alloc(parameters, parameters);
  gsl_multifit_nlinear_covar(gsl_multifit_nlinear_jac(work), 0.0, covariance);
  gsl_set_error_handler(previous);
  const double scale = chi2 / double(n - parameters);
  double* values[] = {&fit.high, &fit.low, &fit.midpoint, &fit.width};
  double* errors[] = {&fit.high_error, &fit.low_error, &fit.midpoint_error, &fit.width_error};
  for (std::size_t k = 0; k < parameters; ++k) {
    *values[k] = gsl_vector_get(p, k);
    *errors[k] = std::sqrt(scale * gsl_matrix_get(covariance, k, k));
  }
  fit.residual_sum_of_squares = chi2;
  // A step that falls between two abscissae leaves the width and midpoint undetermined (JᵀJ singular): the
  // errors then blow up, and the fit is reported as not converged.
  bool determined = true;
  for (double* e : errors) determined = determined && std::isfinite(*e);
  determined = determined && fit.midpoint_error < *x_max - *x_min;
  fit.converged = status == GSL_SUCCESS && determined;
  gsl_matrix_free(covariance);
  gsl_multifit_nlinear_free(work);
  return fit;
}

}  // namespace aggkit

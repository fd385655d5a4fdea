#include "particle/dem/contact_law.hpp"

#include <cmath>
#include <algorithm>
#include <stdexcept>
#include <string>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>

namespace aggkit {

ClippedCollision clipped_collision(double zeta) {
  if (!(zeta >= 0) || !std::isfinite(zeta)) throw std::invalid_argument("clipped_collision: damping ratio must be finite and >= 0");
  // δ'' + 2ζ δ' + δ = 0 while the force k δ + γ δ' = δ + 2ζ δ' (units m* ω0²) is positive.
  double t = 0, overlap = 0, speed = 0;  // at the zero of the force: time, δ, δ' (< 0)
  if (zeta < 1) {
    const double wd = std::sqrt(1 - zeta * zeta);
    // δ = e^{−ζt} sin(wd t)/wd; force ∝ A sin θ + B cos θ with θ = wd t, A = (1 − 2ζ²)/wd, B = 2ζ: the first
    // zero θ in (0, π] has sin θ ∝ B, cos θ ∝ −A.
    const double theta = zeta == 0 ? M_PI : std::atan2(2 * zeta, -(1 - 2 * zeta * zeta) / wd);
    t = theta / wd;
    const double decay = std::exp(-zeta * t);
    overlap = decay * std::sin(theta) / wd;
    speed = decay * (std::cos(theta) - zeta / wd * std::sin(theta));
  } else if (zeta == 1) {
    // δ = t e^{−t}: force ∝ e^{−t}(2 − t), zero at t = 2.
    t = 2;
    overlap = 2 * std::exp(-2.0);
    speed = (1 - 2) * std::exp(-2.0);
  } else {
    // δ = (e^{λ1 t} − e^{λ2 t})/(λ1 − λ2), λ1,2 = −ζ ± s; force zero where e^{(λ1−λ2)t} = (1 + 2ζλ2)/(1 + 2ζλ1).
    const double s = std::sqrt(zeta * zeta - 1);
    const double l1 = -zeta + s, l2 = -zeta - s;
    // 1 + 2ζλ1 = 1 − 2ζ² + 2ζs written without cancellation: −1/(2ζ² − 1 + 2ζs) · 1 ... (2ζ²−1)² − 4ζ²s² = 1.
    const double c1 = -1 / (2 * zeta * zeta - 1 + 2 * zeta * s);
    const double c2 = 1 - 2 * zeta * zeta - 2 * zeta * s;
    t = std::log(c2 / c1) / (l1 - l2);
    const double e1 = std::exp(l1 * t), e2 = std::exp(l2 * t);
    overlap = (e1 - e2) / (l1 - l2);
    speed = (l1 * e1 - l2 * e2) / (l1 - l2);
  }
  // After the force vanishes the spheres separate at constant speed until δ = 0.
  const double restitution = -speed;
  return {restitution, t, t + (restitution > 0 ? overlap / restitution : 0.0)};
}

double formula_damping_ratio(double e) {
  if (!(e > 0 && e <= 1)) throw std::invalid_argument("restitution must lie in (0, 1]");
  const double l = std::log(e);
  return -l / std::sqrt(M_PI * M_PI + l * l);
}

namespace {
double residual(double zeta, void* target) { return clipped_collision(zeta).restitution - *static_cast<double*>(target); }
}  // namespace

double exact_damping_ratio(double e) {
  if (!(e > 0 && e <= 1)) throw std::invalid_argument("restitution must lie in (0, 1]");
  if (e == 1) return 0;
  // Bracket: the formula's ζ returns a restitution above e (clipping only removes the attractive tail).
  double lower = formula_damping_ratio(e), upper = std::max(2 * lower, 0.1);
  while (residual(upper, &e) > 0) {
    lower = upper;
    upper *= 2;
    if (upper > 1e6) throw std::invalid_argument("restitution " + std::to_string(e) + " is below what a damping ratio <= 1e6 reaches");
  }
  if (residual(lower, &e) < 0) lower = 0;
  gsl_function f{&residual, &e};
  gsl_root_fsolver* solver = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
  gsl_root_fsolver_set(solver, &f, lower, upper);
  double root = 0.5 * (lower + upper);
  for (int i = 0; i < 200; ++i) {
    gsl_root_fsolver_iterate(solver);
    root = gsl_root_fsolver_root(solver);
    if (gsl_root_test_interval(gsl_root_fsolver_x_lower(solver), gsl_root_fsolver_x_upper(solver), 0, 1e-12) == GSL_SUCCESS) break;
  }
  gsl_root_fsolver_free(solver);
  return root;
}

}  // namespace aggkit

// Shattering against an independent closed equation. For K = 1 the moments close: summing the rate
// equations gives, with M1 = 1 (cutoff truncation, negligible tail),
//   dM0/dt = -M0^2/2 + λ(t) M0 (1 - M0)
// (the monomer terms cancel), whose fixed point is M0* = 2λ/(1+2λ). The scalar equation is integrated
// here by classical RK4 with a fine step, independently of CVODE, for constant, linear and tabulated λ(t).
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <vector>

#include "analysis/moments.hpp"
#include "solvers/cvode_integrator.hpp"

using namespace aggkit;

namespace {

double closed_m0(const ShatteringRate& lambda, double t_end) {
  auto f = [&](double t, double m) { return -0.5 * m * m + lambda(t) * m * (1.0 - m); };
  const int steps = 200000;
  const double h = t_end / steps;
  double m = 1.0, t = 0.0;
  for (int i = 0; i < steps; ++i, t += h) {
    const double k1 = f(t, m), k2 = f(t + h / 2, m + h / 2 * k1), k3 = f(t + h / 2, m + h / 2 * k2),
                 k4 = f(t + h, m + h * k3);
    m += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return m;
}

double worst_m0_error(const ShatteringRate& lambda, const std::vector<double>& times) {
  AggregationModel model;
  model.kernel = Kernel::constant();
  model.lambda = lambda;
  model.size = 2048;
  model.truncation = Truncation::cutoff;
  model.initial = monodisperse(model.size);
  IntegratorOptions options;
  options.rtol = 1e-10;
  options.atol = 1e-12;
  options.atol_exponent = 3.0;
  double worst = 0.0;
  integrate(model, times, options, [&](double t, std::span<const double> n, double) {
    worst = std::max(worst, relative_error(moment(n, 0.0), closed_m0(lambda, t)));
  });
  return worst;
}

}  // namespace

TEST_CASE("constant kernel with shattering follows the closed M0 equation", "[cvode][shattering]") {
  // λ ≥ 0.3 keeps sizes ≲ 1/λ^2 far below N = 2048, so the cutoff does not matter; RK4 with 2e5 steps
  // is accurate to ~1e-13; CVODE at rtol 1e-10 to ~1e-9.
  CHECK(worst_m0_error(ShatteringRate::constant(0.5), {1.0, 10.0, 50.0}) < 1e-8);
  CHECK(worst_m0_error(ShatteringRate::linear(0.3, 0.02), {1.0, 10.0, 50.0}) < 1e-8);
  CHECK(worst_m0_error(ShatteringRate::table({0.0, 5.0, 20.0}, {1.0, 0.3, 0.6}), {1.0, 10.0, 30.0}) < 1e-8);
}

TEST_CASE("shattering drives M0 to the steady state 2λ/(1+2λ)", "[cvode][shattering]") {
  for (double lambda : {0.3, 1.0, 10.0}) {
    AggregationModel model;
    model.kernel = Kernel::constant();
    model.lambda = ShatteringRate::constant(lambda);
    model.size = 1024;
    model.truncation = Truncation::cutoff;
    model.initial = monodisperse(model.size);
    IntegratorOptions options;
    options.rtol = 1e-9;
    double m0 = 0.0;
    integrate(model, std::vector<double>{400.0}, options,
              [&](double, std::span<const double> n, double) { m0 = moment(n, 0.0); });
    INFO("lambda " << lambda);
    CHECK(m0 == Approx(2 * lambda / (1 + 2 * lambda)).epsilon(1e-7));
  }
}

TEST_CASE("shattering rate laws and their validation", "[shattering][input]") {
  CHECK(ShatteringRate::linear(0.01, -2.5e-5)(200.0) == Approx(0.005));
  const auto table = ShatteringRate::table({0.0, 10.0}, {1.0, 3.0});
  CHECK(table(5.0) == Approx(2.0));
  CHECK(table(20.0) == 3.0);  // held flat beyond the table
  CHECK_THROWS_WITH(ShatteringRate::linear(0.01, -1e-4).validate(200.0),
                    Catch::Contains("lambda") && Catch::Contains("-0.01"));
  CHECK_THROWS_WITH(ShatteringRate::constant(NAN).validate(1.0), Catch::Contains("nan"));
  CHECK_THROWS_WITH(ShatteringRate::constant(-0.1).validate(1.0), Catch::Contains(">= 0"));
  CHECK_NOTHROW(ShatteringRate::linear(0.01, -2.5e-5).validate(400.0));
}

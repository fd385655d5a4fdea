// DSMC against CVODE for the ballistic kernel with shattering, λ = 0.01, monodisperse ([Kalinov2022,
// Table 2]): ensemble means of M0, M2, M3 at t = 1 and 10 within a few standard errors of the integrated
// equations.
#include <catch2/catch.hpp>

#include <cmath>

#include "analysis/moments.hpp"
#include "solvers/cvode_integrator.hpp"
#include "tests/particle/dsmc/dsmc_fixture.hpp"

using namespace aggkit;

TEST_CASE("dsmc: ballistic kernel, lambda = 0.01: M0, M2, M3 agree with CVODE within a few standard errors") {
  const std::vector<double> times{1.0, 10.0};
  const std::vector<double> orders{0.0, 2.0, 3.0};
  // Reference: CVODE at N = 2000 (the mass beyond 2000 is below 1e-9 at t = 10), rtol 1e-8.
  AggregationModel model = aggkit::testing::dsmc_model(Kernel::ballistic(), 0.01, 2000);
  IntegratorOptions tight;
  tight.rtol = 1e-8;
  std::vector<std::vector<double>> reference;
  integrate(model, times, tight, [&](double, std::span<const double> n, double) {
    reference.push_back({moment(n, 0.0), moment(n, 2.0), moment(n, 3.0)});
  });
  struct Case {
    dsmc::Method method;
    std::uint64_t particles;
  };
  for (const Case c : {Case{dsmc::Method::acceptance_rejection, 20000}, Case{dsmc::Method::fast, 4000}}) {
    dsmc::Options options;
    options.method = c.method;
    options.particles = c.particles;
    options.runs = 16;
    options.seed = 77;
    const auto values = aggkit::testing::ensemble_moments(model, options, times, orders);
    for (std::size_t i = 0; i < times.size(); ++i)
      for (std::size_t p = 0; p < orders.size(); ++p) {
        const auto estimate = dsmc::mean_and_error(values[i][p]);
        INFO("method " << dsmc::to_string(c.method) << ", t = " << times[i] << ", M" << orders[p] << ": "
                       << estimate.mean << " ± " << estimate.standard_error << " vs " << reference[i][p]);
        // 5 standard errors of a 16-run mean (t-distribution, 15 degrees of freedom: P(|t| > 5) ~ 2e-4 per
        // check, 12 checks per method) plus 0.5 % for the O(1/N) bias of a finite particle system.
        CHECK(std::abs(estimate.mean - reference[i][p]) <= 5.0 * estimate.standard_error + 5e-3 * reference[i][p]);
      }
  }
}

// DSMC against the exact solution of the constant kernel (λ = 0, unit monodisperse start):
// M0 = 2/(t+2), M2 = 1 + t ([Leyvraz2003, Sec. 2]).
#include <catch2/catch.hpp>

#include <cmath>

#include "solvers/exact_solutions.hpp"
#include "tests/particle/dsmc/dsmc_fixture.hpp"

using namespace aggkit;
using aggkit::testing::dsmc_model;
using aggkit::testing::ensemble_moments;

TEST_CASE("dsmc: constant kernel moments agree with the exact solution within a few standard errors") {
  const std::vector<double> times{0.5, 2.0, 8.0};
  for (const auto method : {dsmc::Method::acceptance_rejection, dsmc::Method::fast}) {
    dsmc::Options options;
    options.method = method;
    options.particles = 4000;
    options.runs = 24;
    options.seed = 11;
    const auto values = ensemble_moments(dsmc_model(Kernel::constant(), 0.0), options, times, {0.0, 2.0});
    for (std::size_t i = 0; i < times.size(); ++i) {
      INFO("method " << dsmc::to_string(method) << ", t = " << times[i]);
      // M0: every accepted pair removes one particle and trials take the mean waiting time 2V/(N(N-1)), so
      // N(t) is deterministic here; it follows dM0/dt = -M0^2/2 up to O(1/N) = 2.5e-4.
      const auto m0 = dsmc::mean_and_error(values[i][0]);
      CHECK(m0.mean == Approx(exact_moment("constant", 0.0, times[i])).epsilon(1e-3));
      // M2 fluctuates: within 4 standard errors of the mean of 24 runs (t-distribution, 23 degrees of
      // freedom: P(|t| > 4) ~ 6e-4), plus 0.2 % for the O(1/N) bias of 4000 particles.
      const auto m2 = dsmc::mean_and_error(values[i][1]);
      const double exact = exact_moment("constant", 2.0, times[i]);
      CHECK(std::abs(m2.mean - exact) <= 4.0 * m2.standard_error + 2e-3 * exact);
      CHECK(m2.standard_error > 0.0);
    }
  }
}

TEST_CASE("dsmc: the error shrinks like N^-1/2 when the particle count grows 16x") {
  // Root-mean-square error of M2 at t = 4 over 40 runs, at N(0) = 500 and 8000. For an RMS over R = 40
  // runs the relative sampling uncertainty is about 1/sqrt(2R) = 11 %, so the ratio of two (ideally
  // sqrt(16) = 4) has about 16 % uncertainty: the band [2.6, 6.0] is ±2.5 of those standard deviations
  // (the O(1/N) bias, ~1e-3 relative at N = 500, is far below the ~3 % noise).
  const double t = 4.0, exact = exact_moment("constant", 2.0, t);
  std::vector<double> rms;
  for (std::uint64_t particles : {500ULL, 8000ULL}) {
    dsmc::Options options;
    options.particles = particles;
    options.runs = 40;
    options.seed = 5;
    const auto values = ensemble_moments(dsmc_model(Kernel::constant(), 0.0), options, {t}, {2.0});
    double squares = 0.0;
    for (double m2 : values[0][0]) squares += (m2 - exact) * (m2 - exact);
    rms.push_back(std::sqrt(squares / 40.0) / exact);
  }
  INFO("relative RMS error of M2: " << rms[0] << " (500 particles), " << rms[1] << " (8000)");
  CHECK(rms[0] / rms[1] > 2.6);
  CHECK(rms[0] / rms[1] < 6.0);
}

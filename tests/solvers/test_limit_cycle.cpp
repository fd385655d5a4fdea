// Periodic orbits by shooting (solvers/limit_cycle.hpp): the period against a long time series, the orbit's
// periodicity, the Floquet multipliers of a stable cycle, and clear errors for bad options and starts.
#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>
#include <vector>

#include "analysis/input_error.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/limit_cycle.hpp"

using namespace aggkit;

namespace {

// Graded grid K = 32, r = 1.1 up to N = 2^20 (about 140 classes): the tail e^{-0.65 λ k} is resolved for
// λ ≥ 1e-3 (λN ≥ 8).
AggregationModel brownian(double a, double lambda) {
  AggregationModel model;
  model.kernel = Kernel::brownian(a);
  model.lambda = ShatteringRate::constant(lambda);
  model.size = std::size_t(1) << 20;
  model.truncation = Truncation::drop;
  model.initial = {1.0};
  model.grid.resolved = 32;
  model.grid.ratio = 1.1;
  return model;
}

// The period of M0 in a long CVODE run, independently of the shooting code: the mean spacing of the upward
// crossings of M0 through its mean over the last `cycles` cycles, each crossing linearly interpolated between
// outputs 1/400 of a period apart (interpolation error ~1e-6 of a period per crossing).
double time_series_period(const AggregationModel& model, double period, double settle, int cycles) {
  const double spacing = period / 400.0, end = settle + cycles * period;
  std::vector<double> times, m0;
  for (double t = settle; t <= end; t += spacing) times.push_back(t);
  IntegratorOptions options;
  options.rtol = 1e-10;
  integrate(model, times, options, [&](double, std::span<const double> n, double) {
    double sum = 0.0;
    for (double v : n) sum += v;
    m0.push_back(sum);
  });
  double mean = 0.0;
  for (double v : m0) mean += v;
  mean /= double(m0.size());
  std::vector<double> up;
  for (std::size_t i = 1; i < m0.size(); ++i)
    if (m0[i - 1] < mean && m0[i] >= mean) up.push_back(times[i - 1] + spacing * (mean - m0[i - 1]) / (m0[i] - m0[i - 1]));
  REQUIRE(up.size() >= 3);
  return (up.back() - up.front()) / double(up.size() - 1);
}

std::string describe(const LimitCycle& cycle) {
  std::ostringstream text;
  text << cycle.note << " period " << cycle.period << ", Newton " << cycle.newton_iterations << ", GMRES "
       << cycle.krylov_iterations << ", period maps " << cycle.period_maps << ", " << cycle.seconds << " s, residual "
       << cycle.residual << "; multipliers";
  for (auto mu : cycle.floquet) text << " " << mu << " (|mu| " << std::abs(mu) << ")";
  return text.str();
}

}  // namespace

TEST_CASE("limit cycles by shooting: the period of a long time series to 1e-3, a periodic orbit, stable multipliers", "[cycle]") {
  // Both points lie below λ_crit (0.0127 at a = 0.95, 0.0041 at a = 0.8 on the converged curve) where the run
  // settles on an attracting cycle. The time series' period is measured over 40 cycles after the transient.
  const auto [a, lambda, settle] = GENERATE(std::make_tuple(0.95, 0.01, 3000.0), std::make_tuple(0.8, 0.0025, 8000.0));
  const AggregationModel model = brownian(a, lambda);
  const std::optional<CycleStart> start = cycle_start_from_run(model, settle, 0.5);
  REQUIRE(start);
  // A period guess 1 % off: Newton must find T itself (the run's own estimate is already within 1e-5).
  const LimitCycle cycle = find_limit_cycle(model, start->state, 1.01 * start->period);
  INFO("a = " << a << ", lambda = " << lambda << ": " << describe(cycle));
  REQUIRE(cycle.converged);
  const double reference = time_series_period(model, cycle.period, settle, 40);
  INFO("time series period " << reference);
  CHECK(std::abs(cycle.period / reference - 1.0) < 1e-3);
  // One period of the orbit comes back to its start (M0..M3 to the shooting tolerance's order).
  REQUIRE(cycle.orbit_moments.size() == 201);
  for (int p = 0; p < 4; ++p) {
    INFO("M" << p << ": relative change over a period " << cycle.orbit_moments.back()[p] / cycle.orbit_moments.front()[p] - 1.0);
    CHECK(std::abs(cycle.orbit_moments.back()[p] / cycle.orbit_moments.front()[p] - 1.0) < 1e-5);
  }
  CHECK(cycle.orbit_time.back() == Approx(cycle.period).epsilon(1e-12));
  CHECK(cycle.m0_max > cycle.m0_min * (1 + 1e-3));
  // An attracting cycle: the trivial multiplier removed, every other |μ| < 1.
  REQUIRE(cycle.floquet_converged);
  REQUIRE(cycle.floquet.size() == 4);
  CHECK(std::abs(cycle.floquet.front()) < 1.0);
  CHECK(cycle.stable);
}

TEST_CASE("limit cycle: bad options and starts are refused with the key", "[cycle]") {
  const AggregationModel model = brownian(0.95, 0.01);
  const std::vector<double> start(model.unknowns(), 1e-3);
  LimitCycleOptions options;
  options.rtol = 1.0;
  CHECK_THROWS_WITH(find_limit_cycle(model, start, 30.0, options), Catch::Contains("rtol"));
  options = {};
  options.orbit_samples = 1;
  CHECK_THROWS_WITH(find_limit_cycle(model, start, 30.0, options), Catch::Contains("orbit_samples"));
  CHECK_THROWS_WITH(find_limit_cycle(model, start, -1.0), Catch::Contains("period_guess"));
  CHECK_THROWS_WITH(find_limit_cycle(model, std::vector<double>(3, 1.0), 30.0), Catch::Contains("start"));
  AggregationModel driven = model;
  driven.lambda = ShatteringRate::function([](double t) { return 0.01 + 0.001 * std::sin(t); }, "sine");
  CHECK_THROWS_WITH(find_limit_cycle(driven, start, 30.0), Catch::Contains("constant shattering rate"));
}

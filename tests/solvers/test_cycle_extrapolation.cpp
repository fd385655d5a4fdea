// A weakly attracting cycle reached by reduced rank extrapolation of its Poincaré map
// (solvers/cycle_extrapolation.hpp), against the cycle shot by Newton–Krylov from it (solvers/limit_cycle.hpp)
// and against plain relaxation over the same number of periods.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "analysis/input_error.hpp"
#include "solvers/cycle_branch.hpp"
#include "solvers/cycle_extrapolation.hpp"
#include "solvers/hopf_normal_form.hpp"
#include "solvers/limit_cycle.hpp"
#include "solvers/poincare_section.hpp"
#include "tests/solvers/cycle_fixture.hpp"

using namespace aggkit;
using aggkit::testing::graded_brownian;

namespace {

// M0's largest value over [from_period, to_period] periods of a run from `from`, read at CVODE's internal steps
// (rtol 1e-10).
double m0_peak(const AggregationModel& model, const std::vector<double>& from, double period, double from_period,
               double to_period) {
  IntegratorOptions options;
  options.rtol = 1e-10;
  double high = -INFINITY;
  options.on_step = [&](double t, std::span<const double> n) {
    if (t < from_period * period) return;
    double m0 = 0.0;
    for (double v : n) m0 += v;
    high = std::max(high, m0);
  };
  IntegratorRestart restart;
  restart.densities = from;
  integrate(model, std::vector<double>{to_period * period}, options, [](double, std::span<const double>, double) {}, &restart);
  return high;
}

}  // namespace

TEST_CASE("cycle extrapolation: next to the Hopf point RRE reaches the shot cycle in a few rounds", "[cycle]") {
  const double a = 0.95;
  AggregationModel model = graded_brownian(a, 0.1);
  SteadyBranch steady(model, 0.1);
  const HopfPoint hopf = hopf_on_branch(steady, model, a, 1e-6);
  REQUIRE(hopf.found);
  // 1 % below the curve: the normal form's cycle attracts at e^{-2 Re μ T} a period.
  const double lambda = 0.99 * hopf.lambda_crit;
  model.lambda = ShatteringRate::constant(lambda);
  const BranchSteadyState s = steady.at(lambda);
  REQUIRE(s.steady.converged);
  const HopfNormalForm form = hopf_normal_form(model, s.steady.n);
  REQUIRE(form.mu.real() > 0.0);
  const double period = 2.0 * M_PI / form.mu.imag(), radial = std::exp(-2.0 * form.mu.real() * period);
  double level = 0.0;
  for (double v : s.steady.n) level += v;
  const std::vector<double> start = form.cycle_point(s.steady.n);

  CycleExtrapolationOptions options;
  options.rtol = 1e-10;
  options.tolerance = 1e-7;
  const CycleExtrapolation e = extrapolate_cycle(model, start, level, period, options);
  INFO("radial multiplier " << radial << " (" << std::log(1e3) / (2.0 * form.mu.real() * period)
                            << " periods to settle 1e3); " << e.note << ", " << e.seconds << " s");
  REQUIRE(e.converged);

  // Shot from the extrapolated point: Newton–Krylov to 1e-6 (its own, independent convergence test: the scaled
  // periodicity residual of the point it starts from). Measured: residual 1.4e-8 at the start, no Newton step.
  LimitCycleOptions shooting;
  shooting.tolerance = 1e-6;
  shooting.floquet_count = 2;
  const LimitCycle cycle = find_limit_cycle(model, e.state, e.period, shooting);
  INFO("shooting: " << cycle.note << " residual " << cycle.residual << ", Newton " << cycle.newton_iterations << ", period "
                    << cycle.period << " (extrapolated " << e.period << "), |mu_1| " << std::abs(cycle.floquet.front()));
  REQUIRE(cycle.converged);
  CHECK(cycle.newton_iterations == 0);
  // The period against a run of 10 periods from the point (crossings 1/400 of a period apart, interpolation
  // error ~1e-6 of a period each: 1e-5).
  const double series = aggkit::testing::time_series_period(model, e.period, 0.0, 10, e.state);
  INFO("time series period " << series);
  CHECK(std::abs(e.period / series - 1.0) < 1e-5);
  // The largest multiplier is the normal form's radial one (measured 0.98310 against 0.98325).
  CHECK(std::abs(std::abs(cycle.floquet.front()) - radial) < 1e-3);

  // Plain relaxation from the normal form's point (on the mass shell) over as many periods is still off by the
  // radial decay's share, 0.983^20 = 0.71 of its start's error: M0's peak over the last period against the cycle's.
  const double half = 0.5 * (cycle.m0_max - cycle.m0_min);
  const double peak = m0_peak(model, e.state, cycle.period, 0.0, 2.0);
  std::vector<double> on_shell = start;
  const std::vector<double> sizes = model.pivots();
  double mass = 0.0;
  for (std::size_t i = 0; i < sizes.size(); ++i) mass += sizes[i] * start[i];
  for (double& v : on_shell) v /= mass;  // the model's mass is 1
  const double plain = m0_peak(model, on_shell, period, double(e.returns), double(e.returns) + 1.0);
  INFO("M0's peak: on the extrapolated cycle " << peak << ", after " << e.returns << " periods of plain relaxation " << plain
                                           << " (half range " << half << ")");
  CHECK(std::abs(plain - peak) > 1e-2 * half);
}

TEST_CASE("cycle extrapolation: bad options and starts are refused with the key", "[cycle]") {
  const AggregationModel model = graded_brownian(0.95, 0.01);
  const std::vector<double> state(model.unknowns(), 1e-3);
  CycleExtrapolationOptions options;
  options.modes = 0;
  CHECK_THROWS_WITH(extrapolate_cycle(model, state, 0.1, 30.0, options), Catch::Contains("modes"));
  options = {};
  options.max_rounds = 0;
  CHECK_THROWS_WITH(extrapolate_cycle(model, state, 0.1, 30.0, options), Catch::Contains("max_rounds"));
  options = {};
  options.tolerance = 0.0;
  CHECK_THROWS_WITH(extrapolate_cycle(model, state, 0.1, 30.0, options), Catch::Contains("tolerance"));
  options = {};
  options.largest_jump = 0.5;
  CHECK_THROWS_WITH(extrapolate_cycle(model, state, 0.1, 30.0, options), Catch::Contains("largest_jump"));
  CHECK_THROWS_WITH(extrapolate_cycle(model, std::vector<double>(3, 1.0), 0.1, 30.0), Catch::Contains("start"));
  CHECK_THROWS_WITH(extrapolate_cycle(model, state, -1.0, 30.0), Catch::Contains("level"));
  CHECK_THROWS_WITH(extrapolate_cycle(model, state, 0.1, 0.0), Catch::Contains("period_guess"));
}

TEST_CASE("Poincare section: the cubic crossing and state of a known curve", "[cycle]") {
  // M0 = sin t on one class, crossing 0.5 upwards at t = π/6 + 2πj; the state there is sin(t) itself.
  UpwardCrossings section(0.5, true);
  std::vector<double> found;
  for (double t = 0.0; t < 13.0; t += 0.1) {
    const std::vector<double> n{std::sin(t)};
    if (section.add(t, n)) {
      found.push_back(section.time());
      CHECK(std::abs(section.state()[0] - 0.5) < 1e-5);
    }
  }
  REQUIRE(found.size() == 2);
  // The cubic through steps 0.1 apart: error ~h^4/24 · |sin''''| ~ 4e-6.
  CHECK(std::abs(found[0] - M_PI / 6.0) < 1e-5);
  CHECK(std::abs(found[1] - (M_PI / 6.0 + 2.0 * M_PI)) < 1e-5);
}

// The Hopf normal form (solvers/hopf_normal_form.hpp) and the cycles continued from it
// (solvers/cycle_branch.hpp): λ_crit on the steady branch against locate_hopf, the first Lyapunov coefficient's
// sign and the cycle it predicts against the cycle shot from the flow (an independent method: CVODE and
// Newton–Krylov shooting, no normal form), and a cycle continued away from the curve against a long time series.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "analysis/input_error.hpp"
#include "solvers/cycle_branch.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/hopf_normal_form.hpp"
#include "tests/solvers/cycle_fixture.hpp"

using namespace aggkit;
using aggkit::testing::time_series_period;
using aggkit::testing::graded_brownian;

TEST_CASE("Hopf normal form: a supercritical bifurcation whose predicted cycle is the one shot from the flow", "[cycle][hopf]") {
  const AggregationModel model = graded_brownian(0.95, 0.1);
  SteadyBranch steady(model, 0.1);
  const HopfPoint hopf = hopf_on_branch(steady, model, 0.95, 1e-6);
  REQUIRE(hopf.found);
  // The same crossing as the bracketed search of locate_hopf (its own continuation from CVODE starts).
  const HopfPoint direct = locate_hopf(model, 0.95, 0.008, 0.02, 1e-7);
  REQUIRE(direct.found);
  CHECK(std::abs(hopf.lambda_crit / direct.lambda_crit - 1.0) < 1e-5);

  CycleBranchOptions options;
  options.start_distance = 0.05;
  CycleBranch branch(model, steady, hopf.lambda_crit, options);
  const HopfNormalForm& form = branch.normal_form();
  INFO("mu = " << form.mu << ", c1 = " << form.c1 << ", l1 = " << form.lyapunov);
  CHECK(form.eigen_residual < 1e-10);
  CHECK(form.mu.real() > 0.0);  // 0.95 λ_crit: the unstable side
  CHECK(form.supercritical());  // l1 < 0: a stable cycle is born below λ_crit (measured l1 = -31.6)
  // The first cycle of the branch (a relaxation run from the normal form's point, then shooting) at 0.95 λ_crit.
  const BranchCycle first = branch.at(branch.start_lambda());
  INFO(first.note << " " << first.cycle.note);
  REQUIRE(first.cycle.converged);
  CHECK(first.cycle.stable);
  // The normal form's amplitude and frequency, with an O(δ) error at δ = 5 % from the curve: measured on
  // this grid M0 half-range 0.040044 predicted against 0.039650 shot (1.0 %), period 27.904 against 27.894
  // (3.6e-4); the bounds are 1.5 times those.
  const double half_range = 0.5 * (first.cycle.m0_max - first.cycle.m0_min);
  INFO("M0 half-range: predicted " << form.m0_half_range() << ", shot " << half_range << "; period predicted "
                                   << 2 * M_PI / form.frequency() << ", shot " << first.cycle.period);
  CHECK(std::abs(form.m0_half_range() / half_range - 1.0) < 0.015);
  CHECK(std::abs(2 * M_PI / form.frequency() / first.cycle.period - 1.0) < 6e-4);
}

TEST_CASE("cycle branch: continued from the Hopf point, the period of a long time series to 1e-3", "[cycle][hopf]") {
  // a = 0.95: λ_crit = 0.01268 on this grid; λ = 0.01 = 0.79 λ_crit, as in test_limit_cycle.cpp, reached by
  // continuation from 0.95 λ_crit, with no run from the steady state.
  const AggregationModel model = graded_brownian(0.95, 0.1);
  SteadyBranch steady(model, 0.1);
  const HopfPoint hopf = hopf_on_branch(steady, model, 0.95, 1e-6);
  REQUIRE(hopf.found);
  CycleBranchOptions options;
  options.start_distance = 0.05;
  CycleBranch branch(model, steady, hopf.lambda_crit, options);
  const BranchCycle cycle = branch.at(0.01);
  INFO(cycle.how << "; " << cycle.note);
  REQUIRE(cycle.cycle.converged);
  CHECK(cycle.cycle.stable);
  AggregationModel at = model;
  at.lambda = ShatteringRate::constant(0.01);
  const double reference = time_series_period(at, cycle.cycle.period, 20 * cycle.cycle.period, 30, cycle.cycle.state);
  INFO("branch period " << cycle.cycle.period << ", time series " << reference);
  CHECK(std::abs(cycle.cycle.period / reference - 1.0) < 1e-3);
}

TEST_CASE("cycle branch and normal form: bad input is refused with the key", "[cycle][hopf]") {
  const AggregationModel model = graded_brownian(0.95, 0.1);
  SteadyBranch steady(model, 0.1);
  CHECK_THROWS_WITH(CycleBranch(model, steady, -1.0), Catch::Contains("lambda_crit"));
  CycleBranchOptions options;
  options.start_distance = 0.9;
  CHECK_THROWS_WITH(CycleBranch(model, steady, 0.01, options), Catch::Contains("start_distance"));
  options = {};
  options.relax_periods = 1.0;
  CHECK_THROWS_WITH(CycleBranch(model, steady, 0.01, options), Catch::Contains("relax_periods"));
  CHECK_THROWS_WITH(hopf_normal_form(model, std::vector<double>(3, 1.0)), Catch::Contains("steady_state"));
}

// The largest Floquet multiplier from the return map (solvers/cycle_return_map.hpp) against Arnoldi on the
// monodromy matrix of the shot cycle (solvers/limit_cycle.hpp), an independent method on the same cycle.
#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>
#include <vector>

#include "analysis/input_error.hpp"
#include "solvers/cycle_return_map.hpp"
#include "solvers/limit_cycle.hpp"
#include "tests/solvers/cycle_fixture.hpp"

using namespace aggkit;
using aggkit::testing::graded_brownian;

namespace {

std::string describe(const ReturnMapMultiplier& m) {
  std::ostringstream text;
  text << m.note << "; |mu| " << m.multiplier << (m.bounded ? " (bound)" : "") << ", " << m.seconds << " s; deviations";
  for (double d : m.deviations) text << " " << d;
  return text.str();
}

}  // namespace

TEST_CASE("return map: the largest Floquet multiplier agrees with Arnoldi's on the shot cycle", "[cycle]") {
  const auto [a, lambda, settle] = GENERATE(std::make_tuple(0.95, 0.01, 3000.0), std::make_tuple(0.95, 0.001, 4000.0),
                                            std::make_tuple(0.8, 0.0025, 8000.0));
  const AggregationModel model = graded_brownian(a, lambda);
  const std::optional<CycleStart> start = cycle_start_from_run(model, settle, 0.5, 1e-6);
  REQUIRE(start);
  LimitCycleOptions shooting;
  shooting.tolerance = 1e-6;
  const LimitCycle cycle = find_limit_cycle(model, start->state, start->period, shooting);
  REQUIRE(cycle.converged);
  REQUIRE(cycle.floquet_converged);
  const double arnoldi = std::abs(cycle.floquet.front());
  const CycleReference reference{cycle.period, cycle.m0_min, cycle.m0_max, 0.0};
  ReturnMapOptions options;
  options.rtol = 1e-8;
  options.floor = 1e-8;
  options.resolved_factor = 10;
  const ReturnMapMultiplier m = return_map_multiplier(model, cycle.state, reference, options);
  INFO("a = " << a << ", lambda = " << lambda << ": Arnoldi |mu| " << arnoldi << " (next " << std::abs(cycle.floquet[1])
              << "); return map: " << describe(m));
  // Power iteration: the fit runs over the last four returns whose period changes lie 10 times above the floor
  // 1e-8 (at rtol 1e-8 they scatter by ~5e-8 once the perturbation has gone), from the second return on. Where
  // the cycle attracts slowly (0.95, 0.01 and 0.8, 0.0025) those are returns 4..7, by when the next multiplier's
  // share has fallen by (0.13/0.63)^4 and (0.16/0.57)^4: measured 0.630 against 0.633 and 0.580 against 0.570.
  // Where it attracts fast (0.95, 0.001) only returns 1..3 rise above the floor, the last only 4 times above the
  // scatter; weighted by (d / floor)², the fit reads 0.0919 against 0.0929 (unweighted 0.063). There the fit
  // starts at return 1, where the next multiplier (0.032, a ratio of 0.35 to the first) still holds a share of
  // 0.35 … 0.35^4 of an equal amplitude, which bends the slope by up to ~10 %: with the rates summed in another
  // order (the far field, solvers/sectional_far_field.hpp) the fourth return rose above the floor too and the
  // fit read 0.0969 against 0.0908 (6.8 %). Hence 10 % there and 5 % where the fit starts at return 4 (three times
  // the largest difference measured there).
  REQUIRE(m.found());
  CHECK_FALSE(m.bounded);
  CHECK(std::abs(m.multiplier / arnoldi - 1.0) < (lambda == 0.001 ? 0.10 : 0.05));
}

TEST_CASE("return map: bad options and references are refused with the key", "[cycle]") {
  const AggregationModel model = graded_brownian(0.95, 0.01);
  const std::vector<double> state(model.unknowns(), 1e-3);
  const CycleReference reference{33.7, 0.08, 0.23, 1e-6};
  ReturnMapOptions options;
  options.perturbation = 0.5;
  CHECK_THROWS_WITH(return_map_multiplier(model, state, reference, options), Catch::Contains("perturbation"));
  options = {};
  options.max_returns = 2;
  CHECK_THROWS_WITH(return_map_multiplier(model, state, reference, options), Catch::Contains("max_returns"));
  options = {};
  options.resolved_factor = 0.5;
  CHECK_THROWS_WITH(return_map_multiplier(model, state, reference, options), Catch::Contains("resolved_factor"));
  CHECK_THROWS_WITH(return_map_multiplier(model, state, CycleReference{-1.0, 0.08, 0.23, 0.0}), Catch::Contains("period"));
  CHECK_THROWS_WITH(return_map_multiplier(model, state, CycleReference{33.7, 0.23, 0.08, 0.0}), Catch::Contains("m0_max"));
  CHECK_THROWS_WITH(return_map_multiplier(model, state, CycleReference{33.7, 0.08, 0.23, -1.0}), Catch::Contains("spread"));
  CHECK_THROWS_WITH(return_map_multiplier(model, std::vector<double>(3, 1.0), reference), Catch::Contains("on_cycle"));
}

TEST_CASE("return map: the estimate from the deviations, and where the noise next to the floor allows only a bound", "[cycle]") {
  ReturnMapMultiplier m;
  // Geometric from d_1 on: the last four above the floor give the ratio exactly.
  estimate_multiplier({1e-3, 1e-4, 5e-5, 2.5e-5, 1.25e-5, 6.25e-6, 1e-8}, 3e-7, m);
  CHECK_FALSE(m.bounded);
  CHECK(std::abs(m.multiplier - 0.5) < 1e-12);
  CHECK(m.multiplier_error < 1e-10);
  // Measured at a = 0.7, λ = 3.16e-9 (floor 1e-7, resolved 3e-7): d_1 and d_2 lie just above the floor and rise,
  // then d_3 falls within it. Their fit read 2.38, a cycle that repels, of a cycle that settled: the last
  // deviation above the floor bounds it instead.
  estimate_multiplier({1.12169e-4, 3.21533e-7, 7.64984e-7, 8.90636e-8}, 3e-7, m);
  INFO(m.note);
  CHECK(m.bounded);
  CHECK(std::abs(m.multiplier - 3e-7 / 7.64984e-7) < 1e-12);
  // Measured at a = 0.75, λ = 1e-3, whose step's periods spread by 7.8e-4: the perturbation moved the period by
  // less than the floor, so no estimate (the bound 3.6 was read before).
  estimate_multiplier({6.45516e-4, 1.51163e-5}, 3.0 * 7.817889927557108e-4, m);
  INFO(m.note);
  CHECK_FALSE(m.found());
  CHECK_FALSE(m.bounded);
  // Too few returns run to tell.
  estimate_multiplier({1e-3, 1e-4}, 3e-7, m);
  CHECK_FALSE(m.found());
}

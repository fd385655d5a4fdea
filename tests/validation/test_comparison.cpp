// Comparisons of engines: the largest relative error over time, where it occurs, NaN and failed engines.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "validation/harness/comparison.hpp"
#include "validation/scene/scene.hpp"

using namespace aggkit;

namespace {

Observation two_series() {
  Observation observe;
  observe.series = {*Observable::from_name("M0"), *Observable::from_name("M2")};
  return observe;
}

EngineRecord record(std::string label, std::vector<std::vector<double>> values) {
  EngineRecord r;
  r.label = std::move(label);
  r.times = {1.0, 2.0, 3.0};
  r.values = std::move(values);
  return r;
}

}  // namespace

TEST_CASE("harness: comparison takes the largest relative error over the output times") {
  const ComparisonPlan plan{"exact", {{"M0", 0.02}, {"M2", 0.001}}, {}};
  const std::vector<EngineRecord> records{
      record("exact", {{1.0, 2.0}, {0.5, 4.0}, {0.25, 0.0}}),
      record("cvode", {{1.01, 2.0}, {0.51, 4.0}, {0.25, 1e-3}}),
  };
  const auto results = compare_engines(plan, two_series(), records);
  REQUIRE(results.size() == 2);
  CHECK(results[0].engine == "cvode");
  CHECK(results[0].reference == "exact");
  CHECK(results[0].observable == "M0");
  CHECK(results[0].max_relative_error == Approx(0.02));  // |0.51 - 0.5| / 0.5 at t = 2
  CHECK(results[0].time == 2.0);
  CHECK(results[0].pass == (results[0].max_relative_error <= 0.02));
  // Where the reference is 0 the error is absolute: 1e-3 at t = 3, within 1e-3.
  CHECK(results[1].max_relative_error == Approx(1e-3));
  CHECK(results[1].time == 3.0);
  CHECK(results[1].pass);
  // The share of the allowed error used: exactly all of it in both (0.01 of 0.02 * 0.5; 1e-3 of 1e-3 * 1).
  CHECK(results[0].tolerance_used == Approx(1.0));
  CHECK(results[1].tolerance_used == Approx(1.0));
}

TEST_CASE("harness: NaN, missing tolerances and failed engines in a comparison") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const ComparisonPlan plan{"exact", {{"M0", 1.0}}, {}};
  std::vector<EngineRecord> records{
      record("exact", {{1.0, 2.0}, {0.5, 4.0}, {0.25, 8.0}}),
      record("cvode", {{1.0, 2.0}, {nan, 4.0}, {0.25, 80.0}}),
  };
  auto results = compare_engines(plan, two_series(), records);
  REQUIRE(results.size() == 2);
  CHECK(std::isnan(results[0].max_relative_error));  // NaN fails any tolerance
  CHECK(results[0].time == 2.0);
  CHECK_FALSE(results[0].pass);
  CHECK(results[1].max_relative_error == Approx(9.0));
  CHECK_FALSE(results[1].tolerance);
  CHECK(results[1].pass);  // reported only
  CHECK(std::isnan(results[0].tolerance_used));
  CHECK(std::isnan(results[1].tolerance_used));  // no tolerance

  records[1].failure = "CVODE failed";
  results = compare_engines(plan, two_series(), records);
  CHECK(std::isnan(results[0].max_relative_error));
  CHECK_FALSE(results[0].pass);
  CHECK(results[0].note == "engine did not complete");
}

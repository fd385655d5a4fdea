// Comparisons of engines: the largest relative error over time, where it occurs, NaN and failed engines.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

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

TEST_CASE("harness: series measures are taken per realization and compared as final values of any engine") {
  // Two realizations oscillating with periods 30 and 32 against one of period 31.5: the ensemble's period
  // is their mean 31 with standard error |32 - 30|/2 = 1 (sample sd √2, over √2), the single run's exactly
  // its own (parabolic turning points: ~1e-6 at T/Δt ~ 30).
  const std::string text = R"(
name = "measures"
[model]
kernel = { name = "constant" }
size = 16
[time]
end = 400.0
every = 1.0
[[engine]]
name = "cvode"
[[engine]]
name = "dsmc"
runs = 2
[observe]
series = ["M0", "M2"]
final = ["oscillation_period:M0", "oscillation_mean:M2"]
window = [100.0, 400.0]
[compare]
reference = "cvode"
)";
  const double two_pi = 2 * std::acos(-1.0);
  const auto wave = [&](double period, double t) { return 1.0 + 0.5 * std::sin(two_pi * t / period); };
  const auto run = [&](const Scene& scene, std::vector<double> periods) {
    EngineRecord r;
    r.label = periods.size() > 1 ? "dsmc" : "cvode";
    for (double t : scene.time.outputs) {
      std::vector<Measurement> at_t;
      // M2 = 1 before the window and 2 + realization inside it: its window mean sees only the window.
      for (std::size_t k = 0; k < periods.size(); ++k)
        at_t.push_back(Measurement{{wave(periods[k], t), t < 100.0 ? 1.0 : 2.0 + double(k)}, 0.0, {}, {}});
      record_measurements(r, scene, t, at_t);
    }
    record_series_measures(r, scene);
    return r;
  };
  for (const auto& [tolerance, passes] : {std::pair{"{ relative = 0.01, stderr = 3 }", true},  // 0.5 <= 0.315 + 3
                                          std::pair{"0.01", false}}) {                           // 0.5 > 0.315
    const Scene scene = parse_scene(text + "final = { \"oscillation_period:M0\" = " + tolerance + " }\n");
    const std::vector<EngineRecord> records{run(scene, {31.5}), run(scene, {30.0, 32.0})};
    REQUIRE(records[1].finals.size() == 2);
    CHECK(records[1].finals[0].name == "oscillation_period:M0");
    CHECK(records[1].finals[0].mean == Approx(31.0).epsilon(1e-4));
    CHECK(records[1].finals[0].standard_error == Approx(1.0).epsilon(1e-3));
    CHECK(records[1].finals[1].mean == Approx(2.5));       // mean of 2 and 3 over the window only
    CHECK(records[1].finals[1].standard_error == Approx(0.5));
    CHECK(records[0].finals[0].standard_error == 0.0);    // one realization
    const auto results = compare_engines(*scene.compare, scene.observe, records);
    REQUIRE(results.size() == 4);  // M0, M2, then the two final values
    CHECK(results[2].final_state);
    CHECK(results[2].observable == "oscillation_period:M0");
    CHECK(results[2].max_relative_error == Approx(0.5 / 31.5).epsilon(1e-3));
    CHECK(results[2].max_standard_errors == Approx(0.5).epsilon(1e-3));
    CHECK(results[2].pass == passes);
    CHECK_FALSE(results[3].tolerance);  // the mean is reported only
  }
}

TEST_CASE("harness: size distributions are compared by their Euclidean distance against standard errors") {
  // Reference n = (0.5, 0.25); two realizations (0.52, 0.25) and (0.50, 0.23): mean (0.51, 0.24), E = 0.01√2;
  // per size the sample variance of the mean is (0.02²/2)/2 = 1e-4, σ = sqrt(2e-4) = 0.01√2, so E = 1 σ;
  // the single-realization errors are 0.02 each.
  const Scene scene = parse_scene(R"(
name = "distributions"
[model]
kernel = { name = "constant" }
size = 2
[time]
end = 1.0
[[engine]]
name = "cvode"
[[engine]]
name = "dsmc"
runs = 2
[observe]
series = ["M0"]
distributions = [1.0]
[compare]
reference = "cvode"
distribution = { relative = 0.0, stderr = 1.01 }
)");
  const auto run = [&](std::string label, std::vector<std::vector<double>> each) {
    EngineRecord r;
    r.label = std::move(label);
    std::vector<Measurement> at_end;
    for (auto& n : each) at_end.push_back(Measurement{{n[0] + n[1]}, 0.0, n, {}});
    record_measurements(r, scene, 1.0, at_end);
    return r;
  };
  std::vector<EngineRecord> records{run("cvode", {{0.5, 0.25}}), run("dsmc", {{0.52, 0.25}, {0.50, 0.23}})};
  auto results = compare_engines(*scene.compare, scene.observe, records);
  REQUIRE(results.size() == 2);
  const ComparisonResult& d = results[1];
  CHECK(d.observable == "distribution");
  CHECK(d.max_relative_error == Approx(0.01 * std::sqrt(2.0) / std::hypot(0.5, 0.25)));
  CHECK(d.max_standard_errors == Approx(1.0));
  CHECK(d.pass);  // 1 σ <= 1.01 σ
  CHECK_THAT(d.note, Catch::Contains("1.41e-02") && Catch::Contains("single realizations: 1: 2.00e-02"));
  ComparisonPlan strict = *scene.compare;
  strict.distribution->standard_errors = 0.99;
  CHECK_FALSE(compare_engines(strict, scene.observe, records)[1].pass);
}

TEST_CASE("harness: final values against stated values, with and without a reference engine") {
  // contacts of two engines against the stated 0.5: |x - v| <= relative |v| + stderr σ, σ the engine's own.
  ComparisonPlan plan;
  plan.final_tolerances = {Tolerance{"contacts", 0.05, 3.0, 0.5}, Tolerance{"aggregation_time_ff", 0.1, std::nullopt, 1.1107}};
  Observation observe;
  observe.series = {*Observable::from_name("clusters")};
  observe.final_state = {"contacts"};
  EngineRecord near = record("near", {{10}, {5}, {1}}), far = record("far", {{10}, {5}, {1}});
  near.finals = {{"contacts", 0.52, 0.001}, {"aggregation_time_ff", 1.2, 0.0}};  // 0.02 <= 0.025; 0.089 <= 0.111
  far.finals = {{"contacts", 0.56, 0.005}};                                       // 0.06 > 0.025 + 0.015; no T_agg
  const auto results = compare_engines(plan, observe, {near, far});
  REQUIRE(results.size() == 4);  // no reference: the stated values only, on every engine
  CHECK(results[0].engine == "near");
  CHECK(results[0].reference == "stated value");
  CHECK(results[0].final_state);
  CHECK(results[0].max_relative_error == Approx(0.04));
  CHECK(results[0].tolerance_used == Approx(0.02 / (0.025 + 0.003)));
  CHECK(results[0].max_standard_errors == Approx(20.0));
  CHECK(results[0].pass);
  CHECK(results[1].observable == "aggregation_time_ff");
  CHECK(results[1].pass);
  CHECK(results[2].engine == "far");
  CHECK_FALSE(results[2].pass);
  CHECK(results[2].tolerance_used == Approx(0.06 / 0.04));
  CHECK(results[3].observable == "aggregation_time_ff");
  CHECK_FALSE(results[3].pass);  // asked for and not reported: a failure, not a pass
  CHECK(std::isnan(results[3].max_relative_error));
  // With a reference engine as well: the stated values on both engines, then the engine against the reference
  // for what has no stated value (the series here).
  plan.reference = "near";
  plan.final_tolerances.resize(1);
  const auto both = compare_engines(plan, observe, {near, far});
  REQUIRE(both.size() == 3);
  CHECK(both[0].reference == "stated value");
  CHECK(both[1].reference == "stated value");
  CHECK(both[2].reference == "near");
  CHECK(both[2].observable == "clusters");
}

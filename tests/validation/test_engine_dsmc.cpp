// The dsmc engine in the harness: the shipped scene where acceptance-rejection, fast DSMC and CVODE must
// agree (exit 0), the series.csv contract (cvode's header plus <name>_stderr columns for an ensemble), and
// comparisons whose tolerance scales with the standard error.
#include <catch2/catch.hpp>

#include <fstream>

#include <nlohmann/json.hpp>

#include "tests/validation/scene_fixture.hpp"
#include "validation/harness/comparison.hpp"
#include "validation/harness/harness.hpp"

using namespace aggkit;

namespace {

EngineRecord record(std::string label, std::vector<std::vector<double>> values,
                    std::vector<std::vector<double>> errors = {}) {
  EngineRecord r;
  r.label = std::move(label);
  r.times = {1.0, 2.0};
  r.values = std::move(values);
  r.standard_errors = std::move(errors);
  return r;
}

}  // namespace

TEST_CASE("harness: the shipped DSMC scene passes with ar, fast and cvode agreeing") {
  const auto out = aggkit::testing::scratch_folder("dsmc-scene");
  const RunOptions options = aggkit::testing::quiet_run(out);
  const Scene scene = load_scene(aggkit::testing::shipped_scene("dsmc-ballistic.toml"));
  const RunResult result = run_scene(scene, options);
  CHECK(result.exit_code == 0);
  CHECK(result.comparisons.size() == 6);
  for (const auto& c : result.comparisons) {
    INFO(c.engine << " " << c.observable << ": " << c.max_standard_errors << " standard errors");
    CHECK(c.pass);
    CHECK(c.max_standard_errors < 5.0);
  }
  CHECK(aggkit::testing::first_line(out / "cvode" / "series.csv") == "t,M0,M2,M3");
  CHECK(aggkit::testing::first_line(out / "dsmc-ar" / "series.csv") == "t,M0,M2,M3,M0_stderr,M2_stderr,M3_stderr");
  std::ifstream in(out / "summary.json");
  const auto summary = nlohmann::json::parse(in);
  const auto& statistics = summary["engines"]["dsmc-fast"]["statistics"];
  CHECK(statistics["method"] == "fast");
  CHECK(statistics["runs"] == 16);
  CHECK(statistics["accepted_events"].get<std::int64_t>() > 0);
  CHECK(summary["comparisons"][0]["tolerance_stderr"] == 5.0);
}

TEST_CASE("harness: a standard-error tolerance allows k combined standard errors at each time") {
  Observation observe;
  observe.series = {*Observable::from_name("M0")};
  // Engine 0.1 above the reference at t = 1 with σ = 0.03 (3.3 standard errors); with σ_ref = 0.04 the
  // combined σ is 0.05: 2 standard errors.
  const std::vector<EngineRecord> records{record("cvode", {{1.0}, {0.5}}),
                                          record("dsmc", {{1.1}, {0.5}}, {{0.03}, {0.0}})};
  auto with = [&](Tolerance tolerance, std::vector<std::vector<double>> reference_errors = {}) {
    auto copy = records;
    copy[0].standard_errors = std::move(reference_errors);
    return compare_engines(ComparisonPlan{"cvode", {tolerance}, {}}, observe, copy).at(0);
  };
  CHECK_FALSE(with({"M0", 0.05}).pass);  // the plain number form: relative error 0.1 > 0.05
  CHECK(with({"M0", 0.11}).pass);
  const auto four = with({"M0", 0.0, 4.0});
  CHECK(four.pass);  // 0.1 <= 4 · 0.03
  CHECK(four.max_standard_errors == Approx(0.1 / 0.03));
  CHECK_FALSE(with({"M0", 0.0, 3.0}).pass);  // 0.1 > 3 · 0.03
  CHECK(with({"M0", 0.0, 4.0}, {{0.0}, {0.0}}).pass);  // σ_ref = 0 changes nothing
  const auto combined = with({"M0", 0.0, 2.0}, {{0.04}, {0.0}});
  CHECK(combined.max_standard_errors == Approx(2.0));  // 0.1 / sqrt(0.03² + 0.04²)
  CHECK(with({"M0", 0.0, 2.01}, {{0.04}, {0.0}}).pass);
  CHECK_FALSE(with({"M0", 0.0, 1.9}, {{0.04}, {0.0}}).pass);
  CHECK(with({"M0", 0.05, 1.7}).pass);  // 0.1 <= 0.05 + 1.7 · 0.03
}

TEST_CASE("scene: the tolerance table form is read and checked") {
  aggkit::testing::SceneText text;
  text.compare = "reference = \"exact\"\ntolerance = { M0 = { relative = 0.01, stderr = 3 }, M2 = 1e-6 }\n";
  const Scene scene = aggkit::testing::parse_checked(text.text());
  REQUIRE(scene.compare->tolerance_for("M0"));
  CHECK(scene.compare->tolerance_for("M0")->relative_error == 0.01);
  CHECK(scene.compare->tolerance_for("M0")->standard_errors == 3.0);
  CHECK_FALSE(scene.compare->tolerance_for("M2")->standard_errors);
  text.compare = "reference = \"exact\"\ntolerance = { M0 = { stderr = -1 } }\n";
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(text.text()), Catch::Matchers::Contains("compare.tolerance.M0.stderr = -1"));
  text.compare = "reference = \"exact\"\ntolerance = { M0 = { sigma = 3 } }\n";
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(text.text()), Catch::Matchers::Contains("sigma"));
  text.compare = "reference = \"exact\"\ntolerance = { M0 = {} }\n";
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(text.text()), Catch::Matchers::Contains("compare.tolerance.M0"));
}

TEST_CASE("engine dsmc: the wall-time budget stops a long ensemble as a failed engine", "[dsmc][harness]") {
  const auto out = aggkit::testing::scratch_folder("dsmc-budget");
  const std::string text = "name = \"budget\"\n[model]\nkernel = { name = \"constant\" }\nlambda = 0.1\nsize = 64\n"
                           "[time]\nend = 1000.0\n[[engine]]\nname = \"dsmc\"\nparticles = 1000000\nmax_wall_seconds = 1e-6\n"
                           "[observe]\nseries = [\"M0\"]\n";
  RunOptions options = aggkit::testing::quiet_run(out);
  const RunResult result = run_scene(aggkit::testing::parse_checked(text), options);
  REQUIRE_FALSE(result.records[0].completed());
  CHECK_THAT(*result.records[0].failure, Catch::Matchers::Contains("max_wall_seconds"));
  CHECK(result.exit_code == 1);
}

TEST_CASE("engine dsmc: population_halving is a scene key, and off a growing population is never halved", "[dsmc][harness]") {
  // Octamers with K = 1, λ = 1: M0 grows from 1/8 towards 2/3, so 2000 particles pass 2 N(0) by t = 4.
  const auto scene = [](const std::string& extra) {
    return "name = \"halving\"\n[model]\nkernel = { name = \"constant\" }\nlambda = 1.0\nsize = 64\n"
           "initial = { kind = \"table\", n = [0, 0, 0, 0, 0, 0, 0, 0.125] }\n[time]\nend = 4.0\n[[engine]]\n"
           "name = \"dsmc\"\nparticles = 2000\n" + extra + "\n[observe]\nseries = [\"M0\"]\n";
  };
  for (const bool halving : {true, false}) {
    const auto out = aggkit::testing::scratch_folder(halving ? "dsmc-halving-on" : "dsmc-halving-off");
    const RunResult result = run_scene(aggkit::testing::parse_checked(scene(halving ? "population_halving = true" : "")),
                                       aggkit::testing::quiet_run(out));
    REQUIRE(result.records[0].completed());
    std::ifstream in(out / "summary.json");
    const auto summary = nlohmann::json::parse(in);
    const auto halvings = summary["engines"]["dsmc"]["statistics"]["halvings"].get<std::int64_t>();
    INFO("population_halving = " << halving << ": " << halvings << " halvings");
    CHECK((halving ? halvings > 0 : halvings == 0));
  }
}

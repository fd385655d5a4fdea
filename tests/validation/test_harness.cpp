// The harness in process: outputs, their format, the numbers against the exact solution, comparisons,
// exit codes, stale outputs and the output folder check.
#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "analysis/input_error.hpp"
#include "tests/validation/scene_fixture.hpp"
#include "validation/harness/harness.hpp"
#include "validation/harness/output_folder.hpp"

using namespace aggkit;
using aggkit::testing::SceneText;
using Catch::Matchers::Contains;

namespace {

RunOptions quiet_options(const std::filesystem::path& out, std::ostream* report = nullptr) {
  RunOptions options = aggkit::testing::quiet_run(out);
  options.report = report;
  return options;
}

}  // namespace

TEST_CASE("harness: constant kernel against the exact solution writes every output and passes") {
  const auto out = aggkit::testing::scratch_folder("harness-constant");
  SceneText text;
  text.observe = "series = [\"M0\", \"M1\", \"M2\", \"n1\", \"mass_leak\"]\ndistributions = [1.0]\n";
  text.compare = "reference = \"exact\"\ntolerance = { M0 = 1e-7, M1 = 1e-7, M2 = 1e-6, n1 = 1e-7 }\n";
  const Scene scene = aggkit::testing::parse_checked(text.text());
  std::ostringstream report;
  const RunResult result = run_scene(scene, quiet_options(out, &report));

  CHECK(result.exit_code == 0);
  CHECK(result.pass);
  CHECK(result.comparisons.size() == 5);  // cvode against exact, each series observable
  CHECK_THAT(report.str(), Contains("PASS") && Contains("M0"));

  for (const char* engine : {"cvode", "exact"}) {
    INFO(engine);
    CHECK(aggkit::testing::first_line(out / engine / "series.csv") == "t,M0,M1,M2,n1,mass_leak");
    const auto rows = aggkit::testing::csv_rows(out / engine / "series.csv");
    REQUIRE(rows.size() == 3);
    // Exact solution, constant kernel [Leyvraz2003]: M0 = 2/(t+2), M1 = 1, M2 = 1 + t, n_1 = 4/(t+2)^2.
    for (const auto& row : rows) {
      const double t = row[0];
      CHECK(row[1] == Approx(2.0 / (t + 2.0)).epsilon(1e-8));
      CHECK(row[2] == Approx(1.0).epsilon(1e-8));
      CHECK(row[3] == Approx(1.0 + t).epsilon(1e-6));
      CHECK(row[4] == Approx(4.0 / ((t + 2.0) * (t + 2.0))).epsilon(1e-8));
      CHECK(std::abs(row[5]) < 1e-12);  // (t+2)^-2 (t/(t+2))^64 ~ 1e-20: nothing leaves by t = 2
    }
    // Distribution at t = 1: one row per size, n_k = 4/9 (1/3)^{k-1}.
    CHECK(aggkit::testing::first_line(out / engine / "distribution.csv") == "t,k,n,cdf");
    const auto distribution = aggkit::testing::csv_rows(out / engine / "distribution.csv");
    REQUIRE(distribution.size() == 64);
    CHECK(distribution[2][0] == 1.0);
    CHECK(distribution[2][1] == 3.0);
    CHECK(distribution[2][2] == Approx(4.0 / 9.0 / 9.0).epsilon(1e-7));
    // CDF of the geometric n_k over the 64 sizes: (1 − 3^-k)/(1 − 3^-64).
    CHECK(distribution[2][3] == Approx(1.0 - 1.0 / 27.0).epsilon(1e-7));
    CHECK(distribution[63][3] == Approx(1.0).epsilon(1e-14));
  }
  CHECK(aggkit::testing::count_files_named(out, "summary.json") == 1);

  const auto summary = nlohmann::json::parse(aggkit::testing::read_text(out / "summary.json"));
  CHECK(summary["pass"] == true);
  CHECK(summary["exit_code"] == 0);
  CHECK(summary["scene"]["name"] == "fixture");
  CHECK(summary["engines"]["cvode"]["status"] == "completed");
  CHECK(summary["engines"]["cvode"]["statistics"]["kernel_rank"] == 1);
  CHECK(summary["engines"]["cvode"]["statistics"]["steps"].get<long>() > 0);
  CHECK(summary["engines"]["cvode"]["wall_seconds"].get<double>() >= 0.0);
  CHECK(summary["engines"]["exact"]["final_mass_leak"] == 0.0);
  CHECK(summary["plot"]["status"] == "skipped");
  REQUIRE(summary["comparisons"].size() == 5);
  const auto& m0 = summary["comparisons"][0];
  CHECK(m0["engine"] == "cvode");
  CHECK(m0["reference"] == "exact");
  CHECK(m0["observable"] == "M0");
  CHECK(m0["max_relative_error"].get<double>() < 1e-7);
  CHECK(m0["tolerance"] == 1e-7);
  CHECK(m0["pass"] == true);
  CHECK(summary["comparisons"][4]["observable"] == "mass_leak");
  CHECK(summary["comparisons"][4]["tolerance"].is_null());  // reported only

  // No temporary file is left behind.
  for (const auto& entry : std::filesystem::recursive_directory_iterator(out))
    CHECK_FALSE(entry.path().string().find(".partial") != std::string::npos);
}

TEST_CASE("harness: a tolerance no solver can meet fails with exit code 1") {
  const auto out = aggkit::testing::scratch_folder("harness-impossible");
  SceneText text;
  text.compare = "reference = \"exact\"\ntolerance = { M2 = 0.0 }\n";
  const RunResult result = run_scene(aggkit::testing::parse_checked(text.text()), quiet_options(out));
  CHECK(result.exit_code == 1);
  CHECK_FALSE(result.pass);
  const auto summary = nlohmann::json::parse(aggkit::testing::read_text(out / "summary.json"));
  CHECK(summary["pass"] == false);
  CHECK(summary["exit_code"] == 1);
  bool failed_m2 = false;
  for (const auto& c : summary["comparisons"])
    if (c["observable"] == "M2") failed_m2 = c["pass"] == false && c["max_relative_error"].get<double>() > 0.0;
  CHECK(failed_m2);
  // The series are still written: they are what shows why.
  CHECK(std::filesystem::exists(out / "cvode" / "series.csv"));
}

TEST_CASE("harness: an output folder under a regular file is refused before anything runs") {
  const auto folder = aggkit::testing::scratch_folder("harness-unwritable");
  const auto file = aggkit::testing::write_text(folder / "file", "not a folder\n");
  try {
    run_scene(aggkit::testing::parse_checked(SceneText{}.text()), quiet_options(file / "out"));
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(e.key() == "--out");
    CHECK_THAT(e.what(), Contains((file / "out").string()));
  }
  // An engine's output folder taken by a file is found before running, too.
  const auto out = folder / "out";
  std::filesystem::create_directories(out);
  aggkit::testing::write_text(out / "exact", "a file where the exact engine's folder goes\n");
  RunOptions forced = quiet_options(out);
  forced.force = true;  // the folder is not aggkit's: without --force it is refused before anything else
  CHECK_THROWS_WITH(run_scene(aggkit::testing::parse_checked(SceneText{}.text()), quiet_options(out)),
                    Contains(out.string()) && Contains("--force"));
  CHECK_THROWS_WITH(run_scene(aggkit::testing::parse_checked(SceneText{}.text()), forced), Contains((out / "exact").string()));
  CHECK_FALSE(std::filesystem::exists(out / "cvode" / "series.csv"));
}

TEST_CASE("harness: stale outputs of an earlier run are removed before a run starts") {
  const auto out = aggkit::testing::scratch_folder("harness-stale");
  const Scene scene = aggkit::testing::parse_checked(SceneText{}.text());
  std::filesystem::create_directories(out / "cvode");
  aggkit::testing::write_text(out / "summary.json", "{\"pass\": true, \"stale\": true}\n");
  aggkit::testing::write_text(out / "cvode" / "series.csv", "stale\n");
  aggkit::testing::write_text(out / "report.png", "stale\n");
  aggkit::testing::write_text(out / "notes.txt", "the user's\n");
  aggkit::testing::write_text(out / ".aggkit-outputs", "summary.json\nreport.png\ncvode/series.csv\n");  // an earlier run's
  OutputFolder(out).prepare({{"cvode", {}}, {"exact", {}}});
  CHECK_FALSE(std::filesystem::exists(out / "summary.json"));
  CHECK_FALSE(std::filesystem::exists(out / "cvode" / "series.csv"));
  CHECK_FALSE(std::filesystem::exists(out / "report.png"));
  CHECK(std::filesystem::exists(out / "notes.txt"));  // not ours: left alone

  const RunResult result = run_scene(scene, quiet_options(out));
  CHECK(result.exit_code == 0);
  const auto summary = nlohmann::json::parse(aggkit::testing::read_text(out / "summary.json"));
  CHECK_FALSE(summary.contains("stale"));
}

TEST_CASE("harness: a rerun removes what the previous run wrote, engines it no longer has included") {
  const auto out = aggkit::testing::scratch_folder("harness-fewer-engines");
  SceneText two;
  two.engines = "[[engine]]\nname = \"cvode\"\n[[engine]]\nname = \"cvode\"\nlabel = \"adams\"\nmethod = \"adams\"\n"
                "[[engine]]\nname = \"exact\"\n";
  REQUIRE(run_scene(aggkit::testing::parse_checked(two.text()), quiet_options(out)).exit_code == 0);
  REQUIRE(std::filesystem::exists(out / "adams" / "series.csv"));
  aggkit::testing::write_text(out / "adams" / "my-notes.txt", "the user's\n");
  REQUIRE(run_scene(aggkit::testing::parse_checked(SceneText{}.text()), quiet_options(out)).exit_code == 0);
  CHECK_FALSE(std::filesystem::exists(out / "adams" / "series.csv"));  // the old engine's output is gone
  CHECK(std::filesystem::exists(out / "adams" / "my-notes.txt"));       // what aggkit did not write stays
  CHECK(std::filesystem::exists(out / "cvode" / "series.csv"));
}

TEST_CASE("harness: a non-empty folder aggkit did not write is refused unless forced") {
  const auto out = aggkit::testing::scratch_folder("harness-foreign");
  aggkit::testing::write_text(out / "thesis.tex", "\\documentclass{article}\n");
  try {
    run_scene(aggkit::testing::parse_checked(SceneText{}.text()), quiet_options(out));
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(e.key() == "--out");
    CHECK_THAT(e.what(), Contains("--force"));
  }
  CHECK_FALSE(std::filesystem::exists(out / "cvode"));
  RunOptions forced = quiet_options(out);
  forced.force = true;
  CHECK(run_scene(aggkit::testing::parse_checked(SceneText{}.text()), forced).exit_code == 0);
  CHECK(std::filesystem::exists(out / "thesis.tex"));
  CHECK(run_scene(aggkit::testing::parse_checked(SceneText{}.text()), quiet_options(out)).exit_code == 0);  // marked now
}

TEST_CASE("harness: a folder holding only the write probe of a killed run is taken as new, the probe removed") {
  // A run killed between writing its write probe (validation/runs/run_folder.hpp) and removing it leaves the
  // probe in a folder that holds nothing else; its rerun must not refuse the folder as foreign.
  const auto out = aggkit::testing::scratch_folder("harness-probe");
  aggkit::testing::write_text(out / ".aggkit-write-test-13808", "probe\n");
  CHECK(run_scene(aggkit::testing::parse_checked(SceneText{}.text()), quiet_options(out)).exit_code == 0);
  CHECK_FALSE(std::filesystem::exists(out / ".aggkit-write-test-13808"));
}

namespace {

// An engine that reports its first output and then fails as a solver would (or finds bad input late).
class FailingEngine final : public Engine {
 public:
  FailingEngine(std::string label, bool bad_input) : Engine("failing", std::move(label)), bad_input_(bad_input) {}
  std::string describe() const override { return "fails after one output"; }
  EngineStatistics run(const Scene& scene, const EngineObserver& observer) const override {
    const std::vector<double> n{1.0};
    observer.output(scene.time.outputs.front(), DensityState(n, 0.0));
    if (bad_input_) throw InputError("engine[2].particles", "0", "at least 1");
    throw std::runtime_error("CVODE: too much work at t = 0.7");
  }

 private:
  bool bad_input_;
};

}  // namespace

TEST_CASE("harness: a failing engine is recorded, the others still run, and the run fails") {
  const auto out = aggkit::testing::scratch_folder("harness-engine-failure");
  Scene scene = aggkit::testing::parse_checked(SceneText{}.text());
  std::vector<std::unique_ptr<Engine>> engines = build_engines(scene);
  engines.insert(engines.begin(), std::make_unique<FailingEngine>("broken", false));
  const RunResult result = run_engines(scene, engines, quiet_options(out));
  CHECK(result.exit_code == 1);
  REQUIRE(result.records.size() == 3);
  CHECK_FALSE(result.records[0].completed());
  CHECK(result.records[1].completed());
  CHECK(result.records[2].completed());
  CHECK_FALSE(std::filesystem::exists(out / "broken" / "series.csv"));  // no partial results that look finished
  CHECK(std::filesystem::exists(out / "cvode" / "series.csv"));
  const auto summary = nlohmann::json::parse(aggkit::testing::read_text(out / "summary.json"));
  CHECK(summary["engines"]["broken"]["status"] == "failed");
  CHECK_THAT(summary["engines"]["broken"]["error"].get<std::string>(), Contains("too much work"));
  CHECK(summary["engines"]["broken"]["outputs_reached"] == 1);
  CHECK(summary["pass"] == false);
  bool broken_compared = false;
  for (const auto& c : summary["comparisons"])
    if (c["engine"] == "broken" && c["observable"] == "M0") broken_compared = c["pass"] == false;
  CHECK(broken_compared);
}

TEST_CASE("harness: bad input found while running stops the run without a summary") {
  const auto out = aggkit::testing::scratch_folder("harness-late-input-error");
  Scene scene = aggkit::testing::parse_checked(SceneText{}.text());
  std::vector<std::unique_ptr<Engine>> engines = build_engines(scene);
  engines.push_back(std::make_unique<FailingEngine>("late", true));
  CHECK_THROWS_AS(run_engines(scene, engines, quiet_options(out)), InputError);
  CHECK_FALSE(std::filesystem::exists(out / "summary.json"));
}

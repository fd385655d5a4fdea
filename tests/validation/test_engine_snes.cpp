// Engine "snes" in the harness: the shipped scene brownian-steady (K = 2, λ = 0.5) against the closed
// form n1 = λ/(1+λ), M0 = 2λ/(1+2λ), its distribution.csv, summary statistics and bad options.
#include <catch2/catch.hpp>

#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "analysis/input_error.hpp"
#include "tests/validation/scene_fixture.hpp"
#include "validation/harness/harness.hpp"
#include "validation/scene/scene.hpp"

using namespace aggkit;

TEST_CASE("engine snes: the shipped steady-state scene passes and writes the distribution", "[snes][harness]") {
  const auto out = aggkit::testing::scratch_folder("engine-snes") / "out";
  const RunOptions options = aggkit::testing::quiet_run(out);
  const RunResult result = run_scene(load_scene(aggkit::testing::shipped_scene("brownian-steady.toml")), options);
  CHECK(result.pass);
  std::ifstream csv(out / "snes" / "distribution.csv");
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  CHECK(header == "k,n");
  REQUIRE(row.rfind("1,", 0) == 0);
  // Newton's tolerance 1e-10 on ||F|| bounds the error of n1 by ~1e-10/λ (test_steady_state.cpp).
  CHECK(std::stod(row.substr(2)) == Approx(0.5 / 1.5).epsilon(1e-8));
  const auto summary = nlohmann::json::parse(aggkit::testing::read_text(out / "summary.json"));
  const std::string dump = summary.dump();
  CHECK(dump.find("steady_M0") != std::string::npos);
  CHECK(dump.find("newton_iterations") != std::string::npos);
}

TEST_CASE("engine snes: bad options name the key", "[snes][harness][input]") {
  const std::string scene = R"(name = "s"
[model]
kernel = { name = "brownian", a = 0.5 }
lambda = 0.5
size = 64
truncation = "cutoff"
initial = { kind = "monodisperse" }
[time]
end = 1.0
outputs = [1.0]
[[engine]]
name = "snes"
)";
  const std::string observe = "[observe]\nseries = [\"M0\"]\n";
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(scene + "tolerance = -1.0\n" + observe), Catch::Contains("tolerance") && Catch::Contains("-1"));
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(scene + "rhs = \"fft\"\n" + observe), Catch::Contains("rhs"));
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(scene + "max_newton_iterations = 0\n" + observe), Catch::Contains("max_newton_iterations"));
  std::string driven = scene;
  driven.replace(driven.find("lambda = 0.5"), 12, "lambda = { kind = \"linear\", initial = 0.1, slope = 0.01 }");
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(driven + observe), Catch::Contains("model.lambda"));
}

TEST_CASE("engine snes: petsc_options reach SNES, bad ones are refused before the run", "[snes][harness][input][petsc]") {
  const std::string scene = R"(name = "s"
[model]
kernel = { name = "brownian", a = 0.0 }
lambda = 0.5
size = 256
truncation = "cutoff"
initial = { kind = "monodisperse" }
[time]
end = 1.0
outputs = [1.0]
[observe]
series = ["M0"]
[[engine]]
name = "snes"
start_time = 20.0
)";
  // -snes_max_it 0 allows Newton no step, and its start (the CVODE state at t = 20, rtol 1e-4) is no
  // steady state to 1e-10 (one step from it may be: the first forcing term is tightened near the root):
  // the engine fails and says why.
  const auto out = aggkit::testing::scratch_folder("engine-snes-petsc") / "out";
  const RunResult stopped =
      run_scene(aggkit::testing::parse_checked(scene + "petsc_options = \"-snes_max_it 0\"\n"), aggkit::testing::quiet_run(out));
  REQUIRE(stopped.records.size() == 1);
  REQUIRE(stopped.records[0].failure);
  CHECK_THAT(*stopped.records[0].failure, Catch::Contains("DIVERGED_MAX_IT"));
  // A misspelled option is run past but reported as unread.
  const RunResult misspelled =
      run_scene(aggkit::testing::parse_checked(scene + "petsc_options = \"-snes_rtl 3\"\n"), aggkit::testing::quiet_run(out));
  CHECK(misspelled.pass);
  REQUIRE(misspelled.records[0].warnings.size() == 1);
  CHECK_THAT(misspelled.records[0].warnings[0], Catch::Contains("-snes_rtl 3"));
  // Bad input: not a string, an unknown type, a value that is no number, text that is no option.
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(scene + "petsc_options = 3\n"), Catch::Contains("engine[0].petsc_options"));
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(scene + "petsc_options = \"-ksp_type foo\"\n"),
                    Catch::Contains("engine[0].petsc_options") && Catch::Contains("KSP type foo"));
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(scene + "petsc_options = \"-snes_rtol abc\"\n"),
                    Catch::Contains("engine[0].petsc_options") && Catch::Contains("abc"));
  CHECK_THROWS_AS(aggkit::testing::parse_checked(scene + "petsc_options = \"1e-12\"\n"), InputError);
}

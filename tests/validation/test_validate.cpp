// The pieces of `aggkit validate` that decide what the page and the table say: the scene description, HTML
// escaping of every text, image paths as URLs, the choice of the worst comparison, and the scene selection.
#include <catch2/catch.hpp>

#include "analysis/input_error.hpp"
#include "tests/validation/scene_fixture.hpp"
#include <filesystem>
#include <fstream>

#include "validation/validate/finished_record.hpp"
#include "validation/validate/report_html.hpp"
#include "validation/validate/validation_plan.hpp"

using namespace aggkit;

TEST_CASE("validate: the description is the scene file's opening comment") {
  CHECK(opening_comment("# First line.\n#   indented\n#\n# last\nname = \"x\"\n# not this\n") ==
        "First line.\n  indented\n\nlast");
  CHECK(opening_comment("\n\n# After blank lines\r\n[model]\n") == "After blank lines");
  CHECK(opening_comment("name = \"x\"\n# later\n").empty());
  CHECK(opening_comment("").empty());
}

TEST_CASE("validate: text on the page is escaped and image paths are URLs") {
  CHECK(html_escape("<b>a & \"b\" 'c'</b>") == "&lt;b&gt;a &amp; &quot;b&quot; &#39;c&#39;&lt;/b&gt;");
  CHECK(html_escape("λ_crit(a) ±2σ") == "λ_crit(a) ±2σ");  // UTF-8 passes through (the page is UTF-8)
  CHECK(url_path("scene-1/ed/final.png") == "scene-1/ed/final.png");
  CHECK(url_path("a b/#c?.png") == "a%20b/%23c%3F.png");
}

TEST_CASE("validate: the worst comparison is a failed one, else the one using most of its tolerance") {
  const auto line = [](double error, std::optional<double> tolerance, double used, std::optional<bool> pass) {
    ComparisonLine c;
    c.error = error;
    c.tolerance = tolerance;
    c.tolerance_used = used;
    c.pass = pass;
    return c;
  };
  const double nan = ComparisonLine::nan;
  CHECK_FALSE(worst_comparison({}));
  // Reported-only comparisons (no tolerance) never hide one with a tolerance, even with a larger error.
  CHECK(worst_comparison({line(0.5, std::nullopt, nan, std::nullopt), line(1e-9, 1e-6, 1e-3, true)}) == 1u);
  CHECK(worst_comparison({line(1e-3, 1e-2, 0.1, true), line(1e-8, 1e-7, 0.5, true)}) == 1u);   // share, not error
  CHECK(worst_comparison({line(1e-8, 1e-7, 0.5, true), line(2e-2, 1e-2, 2.0, false)}) == 1u);  // failed first
  CHECK(worst_comparison({line(2e-2, 1e-2, 2.0, false), line(nan, 1e-2, nan, false)}) == 1u);  // NaN is worst
  CHECK(worst_comparison({line(0.1, std::nullopt, nan, std::nullopt), line(0.3, std::nullopt, nan, std::nullopt)}) ==
        1u);
}

TEST_CASE("validate: the plan reads every scene first, tiers, names and bad input") {
  const auto folder = aggkit::testing::scratch_folder("validate-plan");
  const std::string scene = "name = \"NAME\"\nTIER[model]\nkernel = { name = \"constant\" }\nsize = 16\n"
                            "[time]\nend = 1.0\noutputs = [1.0]\n[[engine]]\nname = \"cvode\"\n"
                            "[observe]\nseries = [\"M0\"]\n";
  const auto write = [&](const std::string& file, const std::string& name, const std::string& tier) {
    std::string text = "# " + name + "\n" + scene;
    text.replace(text.find("NAME"), 4, name);
    text.replace(text.find("TIER"), 4, tier.empty() ? "" : "tier = \"" + tier + "\"\n");
    return aggkit::testing::write_text(folder / "scenes" / file, text);
  };
  write("b.toml", "fast one", "");
  write("a.toml", "full/one", "full");
  const std::string scenes = (folder / "scenes").string();
  ValidationPlan plan = plan_validation({scenes}, SceneTier::fast, true);
  REQUIRE(plan.scenes.size() == 1);
  CHECK(plan.scenes[0].name == "fast one");
  CHECK(plan.scenes[0].folder == "fast_one");
  CHECK(plan.scenes[0].description == "fast one");
  CHECK(plan.scenes[0].engines == std::vector<std::string>{"cvode"});
  REQUIRE(plan.notes.size() == 1);
  plan = plan_validation({scenes}, SceneTier::full, true);
  REQUIRE(plan.scenes.size() == 2);
  CHECK(plan.scenes[0].folder == "full_one");  // by file name; '/' is no folder separator
  CHECK(plan.scenes[1].kind == SceneKind::run);
  // The fingerprint follows the text and how the scene is run.
  CHECK(plan.scenes[0].fingerprint != plan_validation({scenes}, SceneTier::full, false).scenes[0].fingerprint);
  CHECK(plan.scenes[0].fingerprint == plan_validation({scenes}, SceneTier::full, true).scenes[0].fingerprint);

  CHECK_THROWS_WITH(parse_tier("slow"), Catch::Contains("--tier = slow") && Catch::Contains("full"));
  CHECK_THROWS_WITH(plan_validation({"no-such-scene"}, SceneTier::fast, true),
                    Catch::Contains("SCENE = no-such-scene") && Catch::Contains("constant-exact"));
  write("c.toml", "fast one", "");  // two scenes, one output folder
  CHECK_THROWS_WITH(plan_validation({scenes}, SceneTier::fast, true),
                    Catch::Contains("name = fast one") && Catch::Contains("b.toml"));
  write("c.toml", "logs", "");  // the validation's own folder
  CHECK_THROWS_AS(plan_validation({scenes}, SceneTier::fast, true), InputError);
}

TEST_CASE("validate: a finished record is read back, and a damaged one is no record") {
  const auto out = std::filesystem::temp_directory_path() / "aggkit-test-finished-record";
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(finished_folder(out));
  PlannedScene scene;
  scene.name = scene.folder = "scene";
  scene.fingerprint = "0123456789abcdef";
  write_finished_record(out, scene, FinishedRecord{1, 2.5});
  const auto record = read_finished_record(out, scene);
  REQUIRE(record);
  CHECK(record->exit_code == 1);
  CHECK(record->wall_seconds == 2.5);
  const auto with = [&](const std::string& text) {
    std::ofstream(finished_folder(out) / "scene.json") << text;
    return read_finished_record(out, scene);
  };
  // A fingerprint of the wrong type (found by fuzz_run_records: it threw nlohmann's type_error), other
  // fields of the wrong type, another scene's fingerprint, an exit code a run cannot have, and not JSON.
  CHECK_FALSE(with(R"({"fingerprint": [1], "exit_code": 0, "wall_seconds": 1.0})"));
  CHECK_FALSE(with(R"({"fingerprint": "0123456789abcdef", "exit_code": "0", "wall_seconds": 1.0})"));
  CHECK_FALSE(with(R"({"fingerprint": "0123456789abcdef", "exit_code": 0, "wall_seconds": [1.0]})"));
  CHECK_FALSE(with(R"({"fingerprint": "fedcba9876543210", "exit_code": 0, "wall_seconds": 1.0})"));
  CHECK_FALSE(with(R"({"fingerprint": "0123456789abcdef", "exit_code": 7, "wall_seconds": 1.0})"));
  CHECK_FALSE(with("{\"fingerprint\": "));
  CHECK(with(R"({"fingerprint": "0123456789abcdef", "exit_code": 0, "wall_seconds": 1.0})"));
  std::filesystem::remove_all(out);
}

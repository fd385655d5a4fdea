// Scene parsing: valid scenes give the right model, engines, grid and observables; every bad input is an
// InputError that names the dotted key and shows the value.
#include <catch2/catch.hpp>

#include <cmath>

#include "analysis/input_error.hpp"
#include "tests/validation/scene_fixture.hpp"
#include "solvers/kernels.hpp"
#include "validation/scan/scan_plan.hpp"
#include "validation/sweep/sweep_plan.hpp"
#include "validation/scene/scene.hpp"

using namespace aggkit;
using aggkit::testing::SceneText;
using Catch::Matchers::Contains;

namespace {

std::vector<std::string> labels(const Scene& scene) {
  std::vector<std::string> out;
  for (const auto& engine : scene.engines) out.push_back(engine.label);
  return out;
}

std::vector<std::string> series(const Scene& scene) {
  std::vector<std::string> out;
  for (const auto& o : scene.observe.series) out.push_back(o.name());
  return out;
}

}  // namespace

TEST_CASE("scene: the fixture scene parses to its model, grid, engines and comparison") {
  const Scene scene = aggkit::testing::parse_checked(SceneText{}.text());
  CHECK(scene.name == "fixture");
  CHECK(scene.model.kernel.name() == "constant");
  CHECK(scene.model.lambda.is_zero());
  CHECK(scene.model.size == 64);
  CHECK(scene.model.truncation == Truncation::drop);
  REQUIRE(scene.model.initial.size() >= 1);
  CHECK(scene.model.initial[0] == 1.0);
  CHECK(scene.initial.kind == InitialCondition::Kind::monodisperse);
  CHECK(scene.time.end == 2.0);
  CHECK(scene.time.outputs == std::vector<double>{0.5, 1.0, 2.0});  // the end is always an output
  CHECK(labels(scene) == std::vector<std::string>{"cvode", "exact"});
  CHECK(scene.engines[0].name == "cvode");
  CHECK_THAT(build_engine(scene, 0)->describe(), Contains("rtol 1e-10"));
  CHECK(series(scene) == std::vector<std::string>{"M0", "M1", "M2"});
  REQUIRE(scene.compare);
  CHECK(scene.compare->reference == "exact");
  REQUIRE(scene.compare->tolerance_for("M0"));
  CHECK(scene.compare->tolerance_for("M0")->relative_error == 1e-6);
  CHECK(scene.compare->tolerance_for("M1") == nullptr);  // reported only
}

TEST_CASE("scene: the tier is fast unless the scene says full") {
  CHECK(aggkit::testing::parse_checked(SceneText{}.text()).tier == SceneTier::fast);
  SceneText text;
  text.top = "name = \"fixture\"\ntier = \"full\"\n";
  CHECK(aggkit::testing::parse_checked(text.text()).tier == SceneTier::full);
  CHECK(std::string(to_string(SceneTier::full)) == "full");
}

TEST_CASE("scene: the README example parses to the ballistic model with shattering") {
  const Scene scene = load_scene(aggkit::testing::shipped_scene("ballistic-shattering.toml"));
  CHECK(scene.name == "ballistic-shattering");
  CHECK(scene.path == aggkit::testing::shipped_scene("ballistic-shattering.toml"));
  CHECK(scene.model.kernel.name() == "ballistic");
  CHECK(scene.model.lambda(0.0) == 0.01);
  CHECK(scene.model.lambda(100.0) == 0.01);
  CHECK(scene.model.size == 5000);
  CHECK(scene.time.outputs.size() == 100);
  CHECK(scene.time.outputs.front() == 1.0);
  CHECK(scene.time.outputs.back() == 100.0);
  CHECK(labels(scene) == std::vector<std::string>{"cvode"});
  CHECK(series(scene) == std::vector<std::string>{"M0", "M2", "M3", "mass_leak"});
  CHECK(scene.observe.distribution_times == std::vector<double>{1.0, 10.0, 100.0});
  // Checked against stated values (the direct right-hand side's means over [50, 100]): no reference engine.
  REQUIRE(scene.compare);
  CHECK(scene.compare->reference.empty());
  REQUIRE(scene.compare->final_tolerances.size() == 3);
  CHECK(scene.compare->final_tolerances[0].observable == "oscillation_mean:M0");
  CHECK(scene.compare->final_tolerances[0].value == 0.087921776426391);
  CHECK(scene.compare->final_tolerances[0].relative_error == 1e-7);
}

TEST_CASE("scene: every shipped scene parses") {
  int scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(aggkit::testing::shipped_scene(""))) {
    if (entry.path().extension() != ".toml") continue;
    INFO(entry.path());
    // Scan scenes (a [scan] section; validation/scan/scan_plan.hpp) are read by the scan's parser.
    if (aggkit::testing::read_text(entry.path()).find("\n[scan]") != std::string::npos)
      CHECK_NOTHROW(load_scan_plan(entry.path()));
    else if (aggkit::testing::read_text(entry.path()).find("\n[sweep]") != std::string::npos)
      CHECK_NOTHROW(load_sweep_plan(entry.path()));  // every point read and built, as `aggkit sweep` does
    else
      CHECK_NOTHROW(build_engines(load_scene(entry.path())));  // engine options and observables checked too
    ++scenes;
  }
  CHECK(scenes >= 5);
}

TEST_CASE("scene: kernel parameters, the forms of lambda(t), cutoff and a tabulated start") {
  SceneText text;
  text.model = "kernel = { name = \"brownian\", a = 0.95 }\n"
               "lambda = { initial = 0.01, slope = -2.5e-5 }\n"
               "size = 128\ntruncation = \"cutoff\"\n"
               "initial = { kind = \"table\", n = [0.5, 0.25] }\n";
  text.engines = "[[engine]]\nname = \"cvode\"\nmethod = \"bdf-dense\"\nrhs = \"direct\"\natol = 1e-12\n"
                 "preconditioner = \"none\"\nkrylov = 10\nlowrank_tolerance = 1e-9\n"
                 "[[engine]]\nname = \"cvode\"\nlabel = \"cvode-adams\"\nmethod = \"adams\"\n";
  text.compare = "reference = \"cvode\"\n";
  const Scene scene = aggkit::testing::parse_checked(text.text());
  CHECK(scene.model.kernel.name() == "brownian");
  CHECK(scene.model.kernel.parameters().at("a") == 0.95);
  CHECK(scene.model.lambda(0.0) == Approx(0.01));
  CHECK(scene.model.lambda(400.0) == Approx(0.0).margin(1e-15));
  CHECK(scene.model.truncation == Truncation::cutoff);
  CHECK(scene.initial.kind == InitialCondition::Kind::table);
  CHECK(scene.model.initial[0] == 0.5);
  CHECK(scene.model.initial[1] == 0.25);
  CHECK(labels(scene) == std::vector<std::string>{"cvode", "cvode-adams"});
  CHECK_THAT(build_engine(scene, 0)->describe(), Contains("bdf-dense") && Contains("direct"));
  CHECK_THAT(build_engine(scene, 1)->describe(), Contains("adams"));

  text.model = "kernel = { name = \"constant\" }\nsize = 16\nlambda = { times = [0, 10], values = [0.0, 0.2] }\n";
  text.engines = "[[engine]]\nname = \"cvode\"\n";
  text.compare = "";
  const Scene tabulated = aggkit::testing::parse_checked(text.text());
  CHECK(tabulated.model.lambda(5.0) == Approx(0.1));
  CHECK_FALSE(tabulated.compare);
}

TEST_CASE("scene: a grid given by `every` ends exactly at the end and matches distribution times") {
  SceneText text;
  text.time = "end = 1.0\nevery = 0.1\n";
  text.observe = "series = [\"M0\", \"M1.5\", \"n3\", \"mass_leak\"]\ndistributions = [0.3, 1.0]\n";
  text.compare = "reference = \"exact\"\ntolerance = { \"M1.5\" = 1e-6, n3 = 1e-6 }\n";
  const Scene scene = aggkit::testing::parse_checked(text.text());
  REQUIRE(scene.time.outputs.size() == 10);
  CHECK(scene.time.outputs.back() == 1.0);
  for (std::size_t i = 1; i < scene.time.outputs.size(); ++i) CHECK(scene.time.outputs[i] > scene.time.outputs[i - 1]);
  // 0.3 is 3 * 0.1 = 0.30000000000000004 on the grid: it matches up to round-off and takes the grid's value.
  REQUIRE(scene.observe.distribution_times.size() == 2);
  CHECK(scene.observe.distribution_times[0] == scene.time.outputs[2]);
  CHECK(series(scene) == std::vector<std::string>{"M0", "M1.5", "n3", "mass_leak"});
  CHECK(scene.observe.series[1].parameter() == 1.5);
  CHECK(scene.observe.series[2].parameter() == 3);

  text.time = "end = 5.0\n";  // no outputs given: the end alone
  text.observe = "series = [\"M0\"]\n";
  text.compare = "";
  CHECK(aggkit::testing::parse_checked(text.text()).time.outputs == std::vector<double>{5.0});
}

TEST_CASE("scene: each bad input is an InputError naming its key and value") {
  for (const auto& bad : aggkit::testing::bad_scenes()) {
    INFO(bad.description << "\n" << bad.text);
    try {
      aggkit::testing::parse_checked(bad.text);
      FAIL_CHECK("accepted");
    } catch (const InputError& e) {
      CHECK(e.key() == bad.key);
      CHECK_THAT(e.what(), Contains(bad.key) && Contains(bad.value));
    }
  }
}

TEST_CASE("scene: unknown keys are named with the keys that are allowed") {
  SceneText text;
  text.engines = "[[engine]]\nname = \"cvode\"\nrtl = 1e-8\n[[engine]]\nname = \"exact\"\n";
  try {
    aggkit::testing::parse_checked(text.text());
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(e.key() == "engine[0].rtl");
    CHECK_THAT(e.what(), Contains("rtol") && Contains("method") && Contains("label"));
  }
  text = SceneText{};
  text.engines = "[[engine]]\nname = \"warp\"\n";
  text.compare = "";
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(text.text()), Contains("engine[0].name") && Contains("cvode") && Contains("exact"));
}

TEST_CASE("scene: a missing, unreadable or malformed scene file is an InputError naming the path") {
  const auto folder = aggkit::testing::scratch_folder("scene-files");
  const auto missing = folder / "missing.toml";
  CHECK_THROWS_WITH(load_scene(missing), Contains(missing.string()) && Contains("No such file"));
  CHECK_THROWS_AS(load_scene(folder), InputError);  // a folder
  const auto malformed = aggkit::testing::write_text(folder / "malformed.toml", "name = \"x\"\n[model\n");
  try {
    load_scene(malformed);
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(e.key() == "scene");
    CHECK_THAT(e.what(), Contains(malformed.string()) && Contains("line 2"));
  }
  const auto empty = aggkit::testing::write_text(folder / "empty.toml", "");
  CHECK_THROWS_WITH(load_scene(empty), Contains("name"));
}

TEST_CASE("scene: the kernel registry is what the parser accepts and what its messages list") {
  // Every registered kernel is read from a scene with each declared parameter, refused without a required
  // one (naming it) and with an undeclared one; an unknown name is refused listing exactly the registry.
  for (const KernelEntry& entry : kernel_registry()) {
    std::string parameters;
    for (const KernelParameter& p : entry.parameters) parameters += ", " + p.name + " = 0.5";
    INFO(entry.name);
    SceneText text;
    text.engines = "[[engine]]\nname = \"cvode\"\n", text.compare = "";
    text.model = "kernel = { name = \"" + entry.name + "\"" + parameters + " }\nsize = 64\n";
    CHECK(aggkit::testing::parse_checked(text.text()).model.kernel.name() == entry.name);
    for (const KernelParameter& p : entry.parameters) {
      if (p.fallback) continue;
      text.model = "kernel = { name = \"" + entry.name + "\" }\nsize = 64\n";
      CHECK_THROWS_WITH(aggkit::testing::parse_checked(text.text()), Contains("model.kernel." + p.name) && Contains(p.allowed));
    }
    text.model = "kernel = { name = \"" + entry.name + "\"" + parameters + ", zeta = 1.0 }\nsize = 64\n";
    CHECK_THROWS_WITH(aggkit::testing::parse_checked(text.text()), Contains("model.kernel.zeta"));
  }
  std::string listed = "one of";
  for (const KernelEntry& entry : kernel_registry()) listed += " " + entry.name;
  SceneText text;
  text.model = "kernel = { name = \"gaussian\" }\nsize = 64\n";
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(text.text()), Contains("model.kernel.name") && Contains(listed));
  CHECK(Kernel::names().size() == kernel_registry().size());
}

TEST_CASE("scene: compare.final values against stated values need no reference, other forms still do") {
  SceneText text;
  text.engines = "[[engine]]\nname = \"cvode\"\n";
  text.observe = "series = [\"M0\"]\nfinal = [\"oscillation_mean:M0\"]\nwindow = [0.5, 2.0]\n";
  text.time = "end = 2.0\nevery = 0.1\n";
  text.compare = "final = { \"oscillation_mean:M0\" = { value = 0.6, relative = 0.01, stderr = 2 }, steps = { value = 10.0, relative = 1.0 } }\n";
  const Scene scene = aggkit::testing::parse_checked(text.text());
  REQUIRE(scene.compare);
  CHECK(scene.compare->reference.empty());
  REQUIRE(scene.compare->final_tolerances.size() == 2);
  const Tolerance& mean = *scene.compare->final_tolerance_for("oscillation_mean:M0");
  CHECK(mean.value == 0.6);
  CHECK(mean.relative_error == 0.01);
  CHECK(mean.standard_errors == 2.0);
  CHECK(scene.compare->final_tolerance_for("steps")->value == 10.0);  // any final value may be stated
  const auto refused = [&](const std::string& compare, const std::string& key, const std::string& value) {
    text.compare = compare;
    INFO(compare);
    try {
      aggkit::testing::parse_checked(text.text());
      FAIL("no InputError");
    } catch (const InputError& e) {
      CHECK(e.key() == key);
      CHECK_THAT(std::string(e.what()), Contains(value));
    }
  };
  // An entry without a value is against a reference engine: the reference is then required, and a second engine.
  refused("final = { \"oscillation_mean:M0\" = 0.01 }\n", "compare.reference", "");
  refused("reference = \"cvode\"\nfinal = { \"oscillation_mean:M0\" = { value = 0.6, relative = 0.01 } }\n",
          "compare.reference", "second engine");
  // The series tolerances take no value; a value is a finite number, with a relative or stderr part.
  text.engines = "[[engine]]\nname = \"cvode\"\n[[engine]]\nname = \"cvode\"\nlabel = \"other\"\n";
  refused("reference = \"cvode\"\ntolerance = { M0 = { value = 1.0, relative = 0.1 } }\n", "compare.tolerance.M0.value", "1");
  refused("final = { steps = { value = nan, relative = 0.1 } }\n", "compare.final.steps.value", "nan");
  refused("final = { steps = { value = 1.0 } }\n", "compare.final.steps", "relative");
}

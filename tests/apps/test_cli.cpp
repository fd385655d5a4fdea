// The `aggkit` binary end to end: exit codes, messages on stderr, and the files a run leaves.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <sys/wait.h>

#include <nlohmann/json.hpp>

#include "tests/apps/command_fixture.hpp"
#include "tests/validation/scene_fixture.hpp"

using aggkit::testing::SceneText;
using Catch::Matchers::Contains;

namespace {

struct Outcome {
  int exit_code;
  std::string out;
  std::string err;
};

using aggkit::testing::quoted;

// Runs `aggkit <arguments>` with stdout and stderr captured in `folder`; `environment` is prefixed.
Outcome aggkit_cli(const std::vector<std::string>& arguments, const std::filesystem::path& folder,
                   const std::string& environment = "") {
  std::string command = environment + " " + quoted(AGGKIT_CLI);
  for (const auto& a : arguments) command.append(" ").append(quoted(a));
  const auto out = folder / "stdout.txt", err = folder / "stderr.txt";
  command.append(" >").append(quoted(out.string())).append(" 2>").append(quoted(err.string()));
  const int status = std::system(command.c_str());
  REQUIRE(WIFEXITED(status));
  return {WEXITSTATUS(status), aggkit::testing::read_text(out), aggkit::testing::read_text(err)};
}

nlohmann::json summary_of(const std::filesystem::path& out) {
  return nlohmann::json::parse(aggkit::testing::read_text(out / "summary.json"));
}

}  // namespace

TEST_CASE("cli: bad input exits 2 naming the key and value, and leaves no outputs") {
  int checked = 0;
  for (const auto& bad : aggkit::testing::bad_scenes()) {
    if (!bad.through_cli) continue;
    INFO(bad.description << "\n" << bad.text);
    const auto folder = aggkit::testing::scratch_folder("cli-bad-" + std::to_string(checked++));
    const auto scene = aggkit::testing::write_text(folder / "scene.toml", bad.text);
    const auto out = folder / "out";
    const Outcome run = aggkit_cli({"run", scene.string(), "--out", out.string(), "--quiet", "--no-plot"}, folder);
    CHECK(run.exit_code == 2);
    CHECK_THAT(run.err, Contains("aggkit: error: ") && Contains(bad.key) && Contains(bad.value));
    CHECK(aggkit::testing::count_files_named(out, "summary.json") == 0);
    CHECK(aggkit::testing::count_files_named(out, "series.csv") == 0);
    CHECK(run.out.empty());
  }
  CHECK(checked >= 12);
}

TEST_CASE("cli: a run refused for bad input leaves no summary of the earlier run in its folder") {
  const auto folder = aggkit::testing::scratch_folder("cli-bad-after-good");
  const auto out = folder / "out";
  const auto good = aggkit::testing::write_text(folder / "good.toml", SceneText{}.text());
  REQUIRE(aggkit_cli({"run", good.string(), "--out", out.string(), "--quiet", "--no-plot"}, folder).exit_code == 0);
  REQUIRE(std::filesystem::exists(out / "summary.json"));
  SceneText text;
  text.model = "kernel = { name = \"constant\" }\nlambda = -0.5\nsize = 64\n";
  const auto bad = aggkit::testing::write_text(folder / "bad.toml", text.text());
  const Outcome run = aggkit_cli({"run", bad.string(), "--out", out.string(), "--quiet", "--no-plot"}, folder);
  CHECK(run.exit_code == 2);
  CHECK_FALSE(std::filesystem::exists(out / "summary.json"));  // no "pass": true from the earlier run
  // A folder aggkit never wrote is refused, and --force writes into it.
  const auto foreign = folder / "foreign";
  aggkit::testing::write_text(foreign / "data.csv", "1,2\n");
  CHECK(aggkit_cli({"run", good.string(), "--out", foreign.string(), "--quiet", "--no-plot"}, folder).exit_code == 2);
  CHECK(aggkit_cli({"run", good.string(), "--out", foreign.string(), "--quiet", "--no-plot", "--force"}, folder).exit_code == 0);
}

TEST_CASE("cli: a missing or unreadable scene exits 2 naming the path") {
  const auto folder = aggkit::testing::scratch_folder("cli-missing");
  const auto missing = folder / "no-such-scene.toml";
  Outcome run = aggkit_cli({"run", missing.string(), "--out", (folder / "out").string()}, folder);
  CHECK(run.exit_code == 2);
  CHECK_THAT(run.err, Contains("aggkit: error: scene = " + missing.string()) && Contains("No such file"));
  CHECK_FALSE(std::filesystem::exists(folder / "out"));

  // Tests run as root, whom permissions do not stop: a folder is the unreadable scene.
  run = aggkit_cli({"run", folder.string(), "--out", (folder / "out").string()}, folder);
  CHECK(run.exit_code == 2);
  CHECK_THAT(run.err, Contains(folder.string()) && Contains("not a folder"));
}

TEST_CASE("cli: an output folder that cannot be created exits 2 before running") {
  const auto folder = aggkit::testing::scratch_folder("cli-unwritable");
  const auto scene = aggkit::testing::write_text(folder / "scene.toml", SceneText{}.text());
  const auto file = aggkit::testing::write_text(folder / "a-file", "a regular file\n");
  const auto out = file / "out";
  const Outcome run = aggkit_cli({"run", scene.string(), "--out", out.string(), "--no-plot"}, folder);
  CHECK(run.exit_code == 2);
  CHECK_THAT(run.err, Contains("aggkit: error: --out = " + out.string()));
  CHECK(run.out.empty());  // nothing ran
}

TEST_CASE("cli: the shipped constant-kernel scene passes against the exact solution") {
  const auto folder = aggkit::testing::scratch_folder("cli-constant-exact");
  const auto out = folder / "out";
  const Outcome run = aggkit_cli(
      {"run", aggkit::testing::shipped_scene("constant-exact.toml").string(), "--out", out.string(), "--quiet"}, folder);
  CHECK(run.exit_code == 0);
  CHECK_THAT(run.out, Contains("PASS") && Contains("M3"));
  CHECK(aggkit::testing::first_line(out / "cvode" / "series.csv") == "t,M0,M1,M2,M3");
  CHECK(aggkit::testing::first_line(out / "exact" / "series.csv") == "t,M0,M1,M2,M3");
  const auto summary = summary_of(out);
  CHECK(summary["pass"] == true);
  CHECK(summary["exit_code"] == 0);
  CHECK(summary["comparisons"].size() == 4);
  for (const auto& c : summary["comparisons"]) CHECK(c["pass"] == true);
  // The plot is drawn where matplotlib is available; a plot failure is recorded and never fails the run.
  const std::string plot = summary["plot"]["status"];
  CHECK((plot == "written" || plot == "failed"));
  if (plot == "written") {
    CHECK(aggkit::testing::read_text(out / "report.png").substr(1, 3) == "PNG");
  } else {
    CHECK_THAT(run.err, Contains("warning: no plot"));
  }
}

TEST_CASE("cli: an impossible tolerance exits 1 and says FAIL") {
  const auto folder = aggkit::testing::scratch_folder("cli-impossible");
  SceneText text;
  text.compare = "reference = \"exact\"\ntolerance = { M0 = 1e-6, M2 = 0.0 }\n";
  const auto scene = aggkit::testing::write_text(folder / "scene.toml", text.text());
  const Outcome run = aggkit_cli({"run", scene.string(), "--out", (folder / "out").string(), "--no-plot"}, folder);
  CHECK(run.exit_code == 1);
  CHECK_THAT(run.out, Contains("FAIL"));
  const auto summary = summary_of(folder / "out");
  CHECK(summary["pass"] == false);
  CHECK(summary["exit_code"] == 1);
}

TEST_CASE("cli: a plotter that cannot run is a warning, not a failure") {
  const auto folder = aggkit::testing::scratch_folder("cli-no-python");
  const auto scene = aggkit::testing::write_text(folder / "scene.toml", SceneText{}.text());
  const Outcome run = aggkit_cli({"run", scene.string(), "--out", (folder / "out").string(), "--quiet"}, folder,
                                 "AGGKIT_PYTHON=/nonexistent/python3");
  CHECK(run.exit_code == 0);
  CHECK_THAT(run.err, Contains("warning: no plot") && Contains("/nonexistent/python3"));
  const auto summary = summary_of(folder / "out");
  CHECK(summary["plot"]["status"] == "failed");
  CHECK_THAT(summary["plot"]["message"].get<std::string>(), Contains("/nonexistent/python3"));
  CHECK_FALSE(std::filesystem::exists(folder / "out" / "report.png"));
  CHECK_FALSE(std::filesystem::exists(folder / "out" / "report.png.partial"));
}

TEST_CASE("cli: --version, kernels and command-line errors") {
  const auto folder = aggkit::testing::scratch_folder("cli-commands");
  Outcome run = aggkit_cli({"--version"}, folder);
  CHECK(run.exit_code == 0);
  CHECK_THAT(run.out, Contains("aggkit 0."));

  run = aggkit_cli({"kernels"}, folder);
  CHECK(run.exit_code == 0);
  CHECK_THAT(run.out, Contains("brownian") && Contains("0 <= a <= 1") && Contains("ballistic") && Contains("genproduct"));

  run = aggkit_cli({}, folder);  // no command
  CHECK(run.exit_code == 2);
  run = aggkit_cli({"run", "scene.toml"}, folder);  // no --out
  CHECK(run.exit_code == 2);
  CHECK_THAT(run.err, Contains("--out"));
  run = aggkit_cli({"run", "scene.toml", "--out", "x", "--fast"}, folder);
  CHECK(run.exit_code == 2);
  run = aggkit_cli({"--help"}, folder);
  CHECK(run.exit_code == 0);
  CHECK_THAT(run.out, Contains("Exit status"));
}

namespace {

struct HelpOption {
  std::string engine, key, default_text, allowed;
};

// The engine options as `aggkit run --help` shows them: "  <engine>: ..." then "    <key> (default D; A): ...".
std::vector<HelpOption> help_options(const std::string& help) {
  std::vector<HelpOption> options;
  const std::regex engine_line("^  ([a-z]+): "), option_line("^    ([a-z_0-9]+) \\(default ([^;]*); (.*)\\): ");
  std::istringstream lines(help.substr(help.find("Engines (")));
  std::string line, engine;
  std::smatch m;
  std::getline(lines, line);  // the heading
  while (std::getline(lines, line)) {
    if (std::regex_search(line, m, engine_line)) engine = m[1];
    else if (std::regex_search(line, m, option_line)) options.push_back({engine, m[1], m[2], m[3]});
    else if (!line.empty() && line[0] != ' ') break;  // the next part of the help
  }
  return options;
}

// The default as a TOML value if it is a literal (a number, true/false, or one of the allowed words); else "".
std::string literal(const HelpOption& option) {
  const std::string& d = option.default_text;
  if (d == "true" || d == "false") return d;
  if (std::regex_match(d, std::regex("-?[0-9.]+(e[-+]?[0-9]+)?"))) return d.find_first_of(".e") == std::string::npos && option.allowed.find("a number") != std::string::npos ? d + ".0" : d;
  if (option.allowed.rfind("one of ", 0) == 0) return "\"" + d + "\"";
  return "";
}

// A scene that the engine runs, with `key = value` among its options.
std::string scene_with(const std::string& engine, const std::string& key, const std::string& value) {
  const bool particles = engine == "ed" || engine == "ts" || engine == "dem";
  std::map<std::string, std::string> options;
  if (engine == "dem") options = {{"restitution", "0.5"}, {"contact_time", "0.05"}};
  options[key] = value;
  std::string text = "name = \"defaults\"\n";
  if (engine == "dem")  // 3-D only
    text += "[particles]\ndimension = 3\ncount = 8\nradius = 0.5\nvolume_fraction = 0.1\nboundary = \"reflecting\"\n"
            "initial = { cloud = \"cube\", speed = 1.0, directions = \"uniform\" }\n";
  else
    text += particles ? "[particles]\ndimension = 2\ncount = 16\nradius = 0.5\nvolume_fraction = 0.2\nboundary = \"reflecting\"\n"
                        "initial = { lattice = \"square\", speed = 1.0, directions = \"uniform\" }\n"
                      : "[model]\nkernel = { name = \"constant\" }\nlambda = 0.1\nsize = 64\n";  // snes needs λ > 0
  text += "[time]\nend = 1.0\n[[engine]]\nname = \"" + engine + "\"\n";
  for (const auto& [k, v] : options) text += k + " = " + v + "\n";
  return text + "[observe]\nseries = [\"" + std::string(particles ? "clusters" : "M0") + "\"]\n";
}

}  // namespace

TEST_CASE("cli: run --help lists every engine with options whose defaults the scene reader accepts and the engine uses") {
  const auto folder = aggkit::testing::scratch_folder("cli-help");
  const Outcome help = aggkit_cli({"run", "--help"}, folder);
  CHECK(help.exit_code == 0);
  for (const aggkit::EngineType& type : aggkit::engine_types()) {
    INFO(type.name);
    CHECK_THAT(help.out, Contains("  " + type.name + ": " + type.description));
    for (const aggkit::OptionSpec& option : type.options)
      CHECK_THAT(help.out, Contains("    " + option.key + " (default " + option.default_text() + "; " + option.allowed() + ")"));
  }
  const std::vector<HelpOption> options = help_options(help.out);
  // Every engine of the suite (DESIGN.md) is listed with options; cvode's are the documented ones.
  std::set<std::string> engines;
  for (const auto& o : options) engines.insert(o.engine);
  CHECK(engines == std::set<std::string>{"cvode", "dem", "dsmc", "ed", "snes", "ts"});  // exact has no options
  CHECK_THAT(help.out, Contains("  exact: "));
  // Each default shown, written into a scene as the option's value, is accepted: it lies in the range the help
  // states and the reader applies. Defaults that are expressions ("rtol/100") or absences ("none") are not values.
  std::size_t literals = 0;
  for (const HelpOption& option : options) {
    const std::string value = literal(option);
    if (value.empty()) continue;
    ++literals;
    INFO(option.engine << "." << option.key << " = " << value << " (allowed: " << option.allowed << ")");
    CHECK_NOTHROW(aggkit::testing::parse_checked(scene_with(option.engine, option.key, value)));
  }
  CHECK(literals >= 50);  // 54 options have literal defaults today
  // The defaults cvode states are the ones it runs with: its record of the options it used (summary.json).
  const auto scene = aggkit::testing::write_text(folder / "cvode.toml", scene_with("cvode", "max_steps", "10000000"));
  const Outcome run = aggkit_cli({"run", scene.string(), "--out", (folder / "cvode-out").string(), "--quiet", "--no-plot"}, folder);
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const nlohmann::json used = summary_of(folder / "cvode-out")["engines"]["cvode"]["statistics"];
  std::size_t compared = 0;
  for (const HelpOption& option : options) {
    // Literal defaults only ("rtol/100" is derived); the floor reported is the one derived from it.
    if (option.engine != "cvode" || !used.contains(option.key) || literal(option).empty() || option.key == "atol_floor") continue;
    INFO("cvode." << option.key << ": help " << option.default_text << ", used " << used[option.key].dump());
    if (used[option.key].is_string()) CHECK(used[option.key].get<std::string>() == option.default_text);
    else CHECK(used[option.key].get<double>() == std::stod(option.default_text));
    ++compared;
  }
  CHECK(compared >= 5);  // method, rhs, preconditioner, rtol, atol_exponent
  for (const aggkit::ObservableType& type : aggkit::observable_types())
    CHECK_THAT(help.out, Contains("  " + type.form + ": "));
  // The table is the one the scene reader checks against: a key it lists is accepted, one it does not is not.
  SceneText text;
  text.engines = "[[engine]]\nname = \"cvode\"\nkrylov = 7\n[[engine]]\nname = \"exact\"\n";
  CHECK_NOTHROW(aggkit::testing::parse_checked(text.text()));
  text.engines = "[[engine]]\nname = \"cvode\"\nkrylof = 7\n[[engine]]\nname = \"exact\"\n";
  CHECK_THROWS_WITH(aggkit::testing::parse_checked(text.text()), Contains("engine[0].krylof"));
}

namespace {

// A scene that once crashed, hung, ran out of memory or printed nonsense, and what aggkit must do now.
struct Hardened {
  std::string what, text, key, value;
};

std::string ed_text(const std::string& particles, const std::string& engine = "stop = \"one_cluster\"\n") {
  return "name = \"probe\"\n[particles]\ndimension = 2\n" + particles + "boundary = \"reflecting\"\n[time]\nend = 1.0\n"
         "[[engine]]\nname = \"ed\"\n" + engine + "[observe]\nseries = [\"clusters\"]\n";
}

std::string kinetic_text(const std::string& model, const std::string& engine, const std::string& series = "[\"M0\"]") {
  return "name = \"probe\"\n[model]\n" + model + "[time]\nend = 1.0\n[[engine]]\n" + engine + "[observe]\nseries = " +
         series + "\n";
}

}  // namespace

TEST_CASE("cli: input that once crashed, hung or printed nonsense exits 2 naming the key, in bounded time") {
  const std::string constant = "kernel = { name = \"constant\" }\nsize = 200\n";
  const std::vector<Hardened> cases{
      {"a count ED cannot hold", ed_text("count = 4294967294\nradius = 0.5\nvolume_fraction = 0.2\n"), "particles.count", "4294967294"},
      {"a speed whose event times underflow", ed_text("count = 100\nradius = 0.5\nvolume_fraction = 0.2\ninitial = { speed = 1e300 }\n"),
       "particles.initial.speed", "1e+300"},
      {"a box positions cannot resolve", ed_text("count = 100\nradius = 0.5\nbox = 1e300\n"), "particles.box", "1e+300"},
      {"a radius whose box overflows", ed_text("count = 100\nradius = 1e300\nvolume_fraction = 0.2\n"), "particles.radius", "1e+300"},
      {"DSMC that would run for days", kinetic_text("kernel = { name = \"constant\" }\nlambda = 1e300\nsize = 200\n",
                                                    "name = \"dsmc\"\nparticles = 1000\n"), "engine[0].particles", "1000"},
      {"DSMC runs = 1e12", kinetic_text(constant, "name = \"dsmc\"\nruns = 1000000000000\n"), "engine[0].runs", "1000000000000"},
      {"DSMC particles = -1", kinetic_text(constant, "name = \"dsmc\"\nparticles = -1\n"), "engine[0].particles", "an integer in 2.."},
      {"CVODE beyond memory", kinetic_text("kernel = { name = \"constant\" }\nsize = 99999999\n", "name = \"cvode\"\n"),
       "model.size", "99999999"},
      {"moments beyond the tolerance's control",
       kinetic_text(constant, "name = \"cvode\"\n", "[\"M0\", \"M100\"]"), "observe.series[1]", "M100"},
      {"a steady state without shattering", kinetic_text(constant, "name = \"snes\"\n"), "model.lambda", "0"},
      {"a float size", kinetic_text("kernel = { name = \"constant\" }\nsize = 200.0\n", "name = \"cvode\"\n"), "model.size", "200.0"},
      {"escape codes in the name", "name = \"\\u001b[31mred\"\n" + kinetic_text(constant, "name = \"cvode\"\n").substr(15), "name",
       "\\u001b"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Hardened& c = cases[i];
    INFO(c.what << "\n" << c.text);
    const auto folder = aggkit::testing::scratch_folder("cli-hardened-" + std::to_string(i));
    const auto scene = aggkit::testing::write_text(folder / "scene.toml", c.text);
    const Outcome run = aggkit_cli({"run", scene.string(), "--out", (folder / "out").string(), "--quiet", "--no-plot"},
                                   folder, "timeout 60");
    CHECK(run.exit_code == 2);
    CHECK_THAT(run.err, Contains("aggkit: error: " + c.key + " = ") && Contains(c.value));
    CHECK(aggkit::testing::count_files_named(folder / "out", "summary.json") == 0);
  }
}

TEST_CASE("cli: a scene nested 40000 levels deep or an endless file is refused, not a crash") {
  const auto folder = aggkit::testing::scratch_folder("cli-deep");
  std::string deep = "name = \"x\"\n[";
  for (int i = 0; i < 40000; ++i) deep += i ? ".a" : "a";
  deep += "]\n";
  const auto scene = aggkit::testing::write_text(folder / "deep.toml", deep);
  const Outcome nested = aggkit_cli({"run", scene.string(), "--out", (folder / "out").string()}, folder);
  CHECK(nested.exit_code == 2);
  CHECK_THAT(nested.err, Contains("at most 64 levels"));
  const Outcome endless = aggkit_cli({"run", "/dev/zero", "--out", (folder / "out").string()}, folder, "timeout 60");
  CHECK(endless.exit_code == 2);
  CHECK_THAT(endless.err, Contains("at most 4 MiB"));
}

TEST_CASE("cli: a scene name that looks like an option still gets its plot") {
  const auto folder = aggkit::testing::scratch_folder("cli-dash-name");
  SceneText text;
  text.top = "name = \"-h\"\n";
  const auto scene = aggkit::testing::write_text(folder / "scene.toml", text.text());
  const Outcome run = aggkit_cli({"run", scene.string(), "--out", (folder / "out").string(), "--quiet"}, folder);
  CHECK(run.exit_code == 0);
  CHECK(summary_of(folder / "out")["plot"]["status"] == "written");
}

TEST_CASE("cli: PETSc options after -- reach the snes engine, bad ones exit 2") {
  const auto folder = aggkit::testing::scratch_folder("cli-petsc-options");
  const auto out = folder / "out";
  const std::string scene = aggkit::testing::shipped_scene("brownian-steady.toml").string();
  // -snes_monitor prints PETSc's residual lines on stdout.
  const Outcome monitored = aggkit_cli({"run", scene, "--out", out.string(), "--quiet", "--no-plot", "--", "-snes_monitor"}, folder);
  CHECK(monitored.exit_code == 0);
  CHECK_THAT(monitored.out, Contains("SNES Function norm"));
  // -snes_max_it 0 allows Newton no step, and its start (a CVODE state) is no steady state to the scene's
  // 1e-10 (one step from it would be: the first forcing term is tightened near the root): the engine fails
  // (exit 1) and the message says why.
  const Outcome stopped = aggkit_cli({"run", scene, "--out", out.string(), "--quiet", "--no-plot", "--", "-snes_max_it", "0"}, folder);
  CHECK(stopped.exit_code == 1);
  CHECK_THAT(stopped.err, Contains("DIVERGED_MAX_IT"));
  // Bad options are bad input, refused before anything runs.
  const Outcome bad = aggkit_cli({"run", scene, "--out", out.string(), "--quiet", "--no-plot", "--", "-ksp_type", "foo"}, folder);
  CHECK(bad.exit_code == 2);
  CHECK_THAT(bad.err, Contains("-ksp_type foo") && Contains("KSP type foo"));
  CHECK_FALSE(std::filesystem::exists(out / "summary.json"));
}

// `aggkit validate` end to end on a folder of small scenes: a passing one, one that fails by an impossible
// tolerance, a full-tier one, a scan scene and two that check nothing (no [compare]; a comparison without a
// tolerance), reported "ran (no check)" and counted apart from the passes — exit codes 0/1/2, the table,
// validation.json, report.html with every image it references present, and resumption after a kill without rerunning finished scenes;
// with --jobs 2 the scan first, on both cores as MPI ranks, with the outputs of --jobs 1.
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdlib>
#include <regex>
#include <set>
#include <sys/wait.h>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/apps/command_fixture.hpp"
#include "tests/validation/scene_fixture.hpp"

using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

struct Outcome {
  int exit_code;
  std::string out, err;
};

using aggkit::testing::quoted;

std::string validate_command(const std::vector<std::string>& arguments) {
  std::string command = quoted(AGGKIT_CLI) + " validate";
  for (const auto& a : arguments) {
    command += ' ';  // appended in two steps: " " + quoted(a) trips GCC 12's -Wrestrict false positive
    command += quoted(a);
  }
  return command;
}

// `environment` ("NAME=value ...") is prefixed to the command.
Outcome validate(const std::vector<std::string>& arguments, const fs::path& folder, const std::string& environment = "") {
  const auto out = folder / "stdout.txt", err = folder / "stderr.txt";
  const int status = std::system((environment + " " + validate_command(arguments) + " >" + quoted(out.string()) +
                                  " 2>" + quoted(err.string()))
                                     .c_str());
  REQUIRE(WIFEXITED(status));
  return {WEXITSTATUS(status), aggkit::testing::read_text(out), aggkit::testing::read_text(err)};
}

// Constant kernel against its exact solution [Leyvraz2003] at N = 256 to t = 10: the tail beyond N weighs
// (10/12)^256 ~ 1e-20, so the errors are CVODE's (measured 4e-12 on M0, 3e-13 on M2 at rtol 1e-10): 1e-6
// passes by a factor > 1e5 and 1e-15 on M2 fails by a factor ~300. About 0.1 s each.
std::string constant_scene(const std::string& name, const std::string& tolerance, const std::string& tier = "fast") {
  return "# A constant-kernel check <exact> & small: \"" + name + "\".\n# Second line of the description.\n"
         "name = \"" + name + "\"\ntier = \"" + tier + "\"\n"
         "[model]\nkernel = { name = \"constant\" }\nsize = 256\ntruncation = \"drop\"\n"
         "[time]\nend = 10.0\noutputs = [0.5, 1.0, 5.0, 10.0]\n"
         "[[engine]]\nname = \"cvode\"\nrtol = 1e-10\natol = 1e-14\n[[engine]]\nname = \"exact\"\n"
         "[observe]\nseries = [\"M0\", \"M2\"]\n"
         "[compare]\nreference = \"exact\"\ntolerance = { M0 = 1e-6, M2 = " + tolerance + " }\n";
}

// 2 x 2 points at N = 128 (cutoff), t up to 100: a few hundredths of a second each.
const char* const scan_scene = R"(# A tiny oscillation scan.
name = "tiny-scan"
[model]
kernel = { name = "brownian", a = 0.9 }
size = 128
truncation = "cutoff"
[time]
end = 100.0
every = 1.0
[scan]
a = [0.6, 0.9]
lambda = [0.01, 1.0]
)";

fs::path write_scenes(const fs::path& folder) {
  const fs::path scenes = folder / "scenes";
  aggkit::testing::write_text(scenes / "a-pass.toml", constant_scene("pass-scene", "1e-6"));
  aggkit::testing::write_text(scenes / "b-fail.toml", constant_scene("fail-scene", "1e-15"));
  aggkit::testing::write_text(scenes / "c-full.toml", constant_scene("full-scene", "1e-6", "full"));
  aggkit::testing::write_text(scenes / "d-scan.toml", scan_scene);
  // Nothing checked: one engine and no [compare]; and a comparison with no tolerance (reported only).
  std::string alone = constant_scene("alone-scene", "1e-6");
  alone = alone.substr(0, alone.find("[compare]"));
  alone.replace(alone.find("[[engine]]\nname = \"exact\"\n"), std::string("[[engine]]\nname = \"exact\"\n").size(), "");
  aggkit::testing::write_text(scenes / "e-alone.toml", alone);
  std::string reported = constant_scene("reported-scene", "1e-6");
  reported = reported.substr(0, reported.find("tolerance = "));
  aggkit::testing::write_text(scenes / "f-reported.toml", reported);
  return scenes;
}

nlohmann::json json_of(const fs::path& file) { return nlohmann::json::parse(aggkit::testing::read_text(file)); }

const nlohmann::json& scene_named(const nlohmann::json& validation, const std::string& name) {
  for (const auto& scene : validation["scenes"])
    if (scene["name"] == name) return scene;
  FAIL("no scene " << name << " in validation.json");
  throw std::logic_error("unreachable");
}

// Every src="..." of the page: the images it shows.
std::vector<std::string> image_sources(const std::string& html) {
  std::vector<std::string> sources;
  const std::regex source("<img src=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), source); it != std::sregex_iterator(); ++it)
    sources.push_back((*it)[1]);
  return sources;
}

// The page of the five fast scenes of write_scenes: escaped description, every scene, and every image it
// references present beside it.
void check_report_page(const fs::path& out) {
  const std::string html = aggkit::testing::read_text(out / "report.html");
  CHECK_THAT(html, Contains("A constant-kernel check &lt;exact&gt; &amp; small: &quot;pass-scene&quot;.\nSecond line"));
  CHECK_THAT(html, Contains("id=\"scene-pass-scene\"") && Contains("id=\"scene-fail-scene\"") &&
                       Contains("id=\"scene-tiny-scan\""));
  CHECK(html.find("<table>") < html.find("<section"));  // the summary table first
  CHECK_THAT(html, Contains("1 of 5 scenes pass, 3 ran (no check)") && Contains("<td class=\"nocheck\">ran (no check)</td>"));
  const auto sources = image_sources(html);
  for (const auto& source : sources) {
    INFO(source);
    CHECK(fs::is_regular_file(out / source));
  }
  // ... and every plot the scenes made is on the page (report.png of each run scene and the scan's phase
  // diagram where matplotlib is installed: the harness says whether it drew one).
  std::set<std::string> pngs;
  for (const auto& entry : fs::recursive_directory_iterator(out))
    if (entry.path().extension() == ".png") pngs.insert(entry.path().lexically_relative(out).generic_string());
  CHECK(std::set<std::string>(sources.begin(), sources.end()) == pngs);
  if (json_of(out / "pass-scene" / "summary.json")["plot"]["status"] == "written") {
    CHECK(pngs.count("pass-scene/report.png") == 1);
    CHECK(pngs.count("tiny-scan/phase_diagram.png") == 1);
  }
}

}  // namespace

TEST_CASE("validate cli: a passing and a failing scene give exit 1, the table, validation.json and report.html") {
  const auto folder = aggkit::testing::scratch_folder("validate-cli");
  const fs::path scenes = write_scenes(folder);
  const fs::path out = folder / "out";
  // No MPI launcher (this tier starts no mpirun): the scan holds one core like the others.
  const Outcome result =
      validate({"--tier", "fast", "--jobs", "2", "--out", out.string(), scenes.string()}, folder, "AGGKIT_MPIEXEC=");
  INFO(result.out << result.err);
  REQUIRE(result.exit_code == 1);
  // The table: a header and a row per scene run (the full-tier scene is left out under --tier fast).
  CHECK_THAT(result.out, Contains("scene") && Contains("worst comparison") && Contains("tolerance") &&
                             Contains("wall s") && Contains("result"));
  CHECK(std::regex_search(result.out, std::regex("pass-scene +fast +cvode, exact +cvode M[02] vs exact .* pass\n")));
  CHECK(std::regex_search(result.out, std::regex("fail-scene +fast +cvode, exact +cvode M2 vs exact .*1e-15 .* FAIL\n")));
  CHECK(std::regex_search(result.out, std::regex("tiny-scan +fast +cvode \\(scan\\) +4 points classified .* ran \\(no check\\)\n")));
  CHECK(std::regex_search(result.out, std::regex("alone-scene +fast +cvode +no comparisons .* ran \\(no check\\)\n")));
  CHECK(std::regex_search(result.out, std::regex("reported-scene +fast +cvode, exact +cvode M[02] vs exact .* ran \\(no check\\)\n")));
  CHECK_THAT(result.out, Contains("5 scenes: 1 pass, 3 ran (no check), 1 FAIL\n"));
  CHECK_THAT(result.out, !Contains("full-scene"));
  CHECK_THAT(result.err, Contains("5 scenes (tier fast), 0 finished earlier, 5 to run, 2 at a time") &&
                             Contains("fail-scene: FAIL") && Contains("alone-scene: ran (no check)"));
  // The scan first (on one core without a launcher), and each line says the cores its scene holds.
  CHECK_THAT(result.err, Contains("no MPI launcher (set AGGKIT_MPIEXEC): scan scenes start first, on one core each") &&
                             Contains("started tiny-scan on 1 core\n") && Contains("started pass-scene on 1 core\n") &&
                             Contains(" s on 1 core)\n"));
  CHECK(result.err.find("started tiny-scan") < result.err.find("started pass-scene"));

  const nlohmann::json validation = json_of(out / "validation.json");
  CHECK(validation["exit_code"] == 1);
  CHECK(validation["pass"] == false);
  CHECK(validation["counts"]["scenes"] == 5);
  CHECK(validation["counts"]["pass"] == 1);
  CHECK(validation["counts"]["no_check"] == 3);
  CHECK(validation["counts"]["fail"] == 1);
  for (const char* name : {"tiny-scan", "alone-scene", "reported-scene"}) {
    INFO(name);
    CHECK(scene_named(validation, name)["result"] == "ran (no check)");
  }
  CHECK_THAT(scene_named(validation, "alone-scene")["problem"].get<std::string>(), Contains("no comparison with a tolerance"));
  REQUIRE(validation["notes"].size() == 1);
  CHECK_THAT(validation["notes"][0].get<std::string>(), Contains("full-scene") && Contains("tier full"));
  const auto& pass = scene_named(validation, "pass-scene");
  CHECK(pass["result"] == "pass");
  CHECK(pass["worst"]["pass"] == true);
  CHECK(pass["worst"]["tolerance_used"].get<double>() < 0.1);  // measured 4e-6 of the tolerance
  CHECK(pass["worst"]["tolerance_used"].get<double>() ==
        Approx(pass["worst"]["max_relative_error"].get<double>() / pass["worst"]["tolerance"].get<double>()));
  const auto& fail = scene_named(validation, "fail-scene");
  CHECK(fail["result"] == "FAIL");
  CHECK(fail["worst"]["observable"] == "M2");
  CHECK(fail["worst"]["pass"] == false);
  CHECK(fail["worst"]["tolerance_used"].get<double>() > 1.0);
  CHECK(fail["failed_comparisons"] == 1);
  CHECK_THAT(fail["problem"].get<std::string>(), Contains("M2") && Contains("outside its tolerance"));
  const auto& scan = scene_named(validation, "tiny-scan");
  CHECK(scan["kind"] == "scan");
  CHECK(scan["scan_points"] == 4);
  CHECK(json_of(out / "pass-scene" / "summary.json")["pass"] == true);  // each scene ran into DIR/<scene>/

  check_report_page(out);
}

TEST_CASE("validate cli: exit 0 when every scene passes, and a scene file named explicitly runs whatever its tier") {
  const auto folder = aggkit::testing::scratch_folder("validate-cli-pass");
  const fs::path scenes = write_scenes(folder);
  const Outcome passing = validate({"--out", (folder / "out-pass").string(), (scenes / "a-pass.toml").string(),
                                    (scenes / "c-full.toml").string()}, folder);
  INFO(passing.out << passing.err);
  CHECK(passing.exit_code == 0);
  CHECK(json_of(folder / "out-pass" / "validation.json")["counts"]["pass"] == 2);
}

TEST_CASE("validate cli: bad input is exit 2, naming the option, the value and what is allowed, before anything runs") {
  const auto folder = aggkit::testing::scratch_folder("validate-cli-bad");
  const fs::path scenes = write_scenes(folder);
  const fs::path bad = folder / "out-bad";
  Outcome refused = validate({"--tier", "medium", "--out", bad.string(), scenes.string()}, folder);
  CHECK(refused.exit_code == 2);
  CHECK_THAT(refused.err, Contains("--tier = medium") && Contains("fast") && Contains("full"));
  refused = validate({"--out", bad.string(), (folder / "no-such-scene.toml").string()}, folder);
  CHECK(refused.exit_code == 2);
  CHECK_THAT(refused.err, Contains("SCENE = ") && Contains("no-such-scene.toml") && Contains("shipped scene"));
  refused = validate({"--jobs", "0", "--out", bad.string(), scenes.string()}, folder);
  CHECK(refused.exit_code == 2);
  CHECK_THAT(refused.err, Contains("--jobs = 0"));
  refused = validate({"--jobs", "2", "--out", bad.string(), scenes.string()}, folder, "AGGKIT_MPIEXEC=/no/such/mpiexec");
  CHECK(refused.exit_code == 2);
  CHECK_THAT(refused.err, Contains("AGGKIT_MPIEXEC = /no/such/mpiexec") && Contains("MPI launcher"));
  aggkit::testing::write_text(folder / "broken" / "x.toml", constant_scene("broken", "-1"));
  refused = validate({"--out", bad.string(), (folder / "broken").string()}, folder);
  CHECK(refused.exit_code == 2);
  CHECK_THAT(refused.err, Contains("tolerance"));
  // Under mpirun every rank would run every scene into the same folder: refused (Open MPI's variable).
  refused = validate({"--out", bad.string(), scenes.string()}, folder, "OMPI_COMM_WORLD_SIZE=2");
  CHECK(refused.exit_code == 2);
  CHECK_THAT(refused.err, Contains("mpirun") && Contains("--jobs"));
  CHECK_FALSE(fs::exists(bad));
  aggkit::testing::write_text(folder / "someone-elses" / "notes.txt", "mine\n");
  refused = validate({"--out", (folder / "someone-elses").string(), scenes.string()}, folder);
  CHECK(refused.exit_code == 2);
  CHECK_THAT(refused.err, Contains("--out = ") && Contains("holds other files"));
}

TEST_CASE("validate cli: a validation killed midway continues without rerunning its finished scenes") {
  const auto folder = aggkit::testing::scratch_folder("validate-cli-resume");
  const fs::path scenes = write_scenes(folder);
  const fs::path out = folder / "out";
  const std::vector<std::string> arguments{"--jobs", "1", "--out", out.string(), (scenes / "a-pass.toml").string(),
                                           (scenes / "b-fail.toml").string()};
  const fs::path pid_file = folder / "pid";
  std::system((validate_command(arguments) + " >/dev/null 2>" + quoted((folder / "killed.txt").string()) +
               " & echo $! > " + quoted(pid_file.string()))
                  .c_str());
  const fs::path record = out / "finished" / "pass-scene.json";
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline && !fs::exists(record))
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  INFO(aggkit::testing::read_text(folder / "killed.txt"));
  REQUIRE(fs::exists(record));
  // Killed while the second scene runs; its child process is ended with it (it gets SIGTERM).
  std::system(("kill -KILL $(cat " + quoted(pid_file.string()) + ") 2>/dev/null; sleep 0.3").c_str());
  const bool second_finished = fs::exists(out / "finished" / "fail-scene.json");
  const auto summary = out / "pass-scene" / "summary.json";
  const auto written = fs::last_write_time(summary);
  const std::string text = aggkit::testing::read_text(summary);

  const Outcome resumed = validate(arguments, folder);
  INFO(resumed.out << resumed.err);
  CHECK(resumed.exit_code == 1);
  CHECK_THAT(resumed.err, Contains(second_finished ? "2 finished earlier, 0 to run" : "1 finished earlier, 1 to run"));
  CHECK(fs::last_write_time(summary) == written);  // not rerun
  CHECK(aggkit::testing::read_text(summary) == text);
  nlohmann::json validation = json_of(out / "validation.json");
  CHECK(scene_named(validation, "pass-scene")["resumed"] == true);
  CHECK(scene_named(validation, "pass-scene")["result"] == "pass");
  CHECK(scene_named(validation, "fail-scene")["result"] == "FAIL");
  CHECK(validation["counts"]["resumed"] == (second_finished ? 2 : 1));
  CHECK_THAT(resumed.out, Contains("finished in an earlier run"));

  // A changed scene file is run again; the unchanged one is still reused.
  aggkit::testing::write_text(scenes / "b-fail.toml",
                              "# changed\n" + aggkit::testing::read_text(scenes / "b-fail.toml"));
  const Outcome changed = validate(arguments, folder);
  CHECK(changed.exit_code == 1);
  CHECK_THAT(changed.err, Contains("1 finished earlier, 1 to run"));
  validation = json_of(out / "validation.json");
  CHECK(scene_named(validation, "fail-scene")["resumed"] == false);
  CHECK(fs::last_write_time(summary) == written);

  // --rerun forgets what was finished.
  const Outcome rerun = validate({"--rerun", "--out", out.string(), (scenes / "a-pass.toml").string()}, folder);
  CHECK(rerun.exit_code == 0);
  CHECK_THAT(rerun.err, Contains("0 finished earlier, 1 to run"));
  CHECK(aggkit::testing::read_text(summary) != "");
  CHECK(scene_named(json_of(out / "validation.json"), "pass-scene")["resumed"] == false);
}

// With --jobs 2 and an MPI launcher the scan starts first and takes both cores as two MPI ranks; its outputs,
// the run scene's and the verdicts are those of --jobs 1, where the scan runs in one process.
TEST_CASE("validate cli: --jobs 2 runs a scan scene first on both cores as MPI ranks, with the outputs of --jobs 1", "[mpi]") {
  const auto folder = aggkit::testing::scratch_folder("validate-cli-slots");
  const fs::path scenes = write_scenes(folder);
  const std::vector<std::string> chosen{(scenes / "a-pass.toml").string(), (scenes / "d-scan.toml").string()};
  const auto validate_into = [&](const fs::path& out, const std::string& jobs) {
    std::vector<std::string> arguments{"--jobs", jobs, "--no-plot", "--out", out.string()};
    arguments.insert(arguments.end(), chosen.begin(), chosen.end());
    // The launcher the tests use (root and more ranks than cores are allowed by validate itself).
    return validate(arguments, folder, "AGGKIT_MPIEXEC=" + quoted(AGGKIT_MPIEXEC));
  };
  const Outcome one = validate_into(folder / "one", "1");
  INFO(one.err);
  REQUIRE(one.exit_code == 0);
  CHECK_THAT(one.err, Contains("started tiny-scan on 1 core\n") && !Contains("MPI ranks"));
  const Outcome two = validate_into(folder / "two", "2");
  INFO(two.err << aggkit::testing::read_text(folder / "two" / "logs" / "tiny-scan.log"));
  REQUIRE(two.exit_code == 0);
  CHECK_THAT(two.err, Contains("scan scenes start first, each on the free cores as MPI ranks") &&
                          Contains("started tiny-scan on 2 cores (2 MPI ranks)\n") &&
                          Contains("started pass-scene on 1 core\n") && Contains(" s on 2 cores)\n"));
  CHECK(two.err.find("started tiny-scan") < two.err.find("started pass-scene"));
  for (const char* file : {"tiny-scan/scan.csv", "tiny-scan/lambda_crit.csv", "pass-scene/cvode/series.csv",
                           "pass-scene/exact/series.csv"}) {
    INFO(file);
    REQUIRE(fs::exists(folder / "one" / file));
    CHECK(aggkit::testing::read_text(folder / "one" / file) == aggkit::testing::read_text(folder / "two" / file));
  }
  nlohmann::json a = json_of(folder / "one" / "validation.json"), b = json_of(folder / "two" / "validation.json");
  for (nlohmann::json* v : {&a, &b}) {  // what may differ: wall times and the job count
    v->erase("wall_seconds");
    v->erase("jobs");
    for (auto& scene : (*v)["scenes"]) scene.erase("wall_seconds");
  }
  CHECK(a == b);
}

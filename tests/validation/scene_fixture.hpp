#pragma once
// Helpers shared by the scene, harness and CLI tests: a small valid scene assembled from its sections
// (each test changes one), scratch folders and file reading.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <functional>
#include <string>
#include <vector>

#include "validation/harness/harness.hpp"

namespace aggkit::testing {

// A scene parsed and its engines built: every bad input, engine options included, is an InputError.
inline Scene parse_checked(std::string_view text) {
  Scene scene = parse_scene(text);
  (void)build_engines(scene);
  return scene;
}

// Run options writing into `out` with no plots, report, progress or warnings (silent test runs).
inline RunOptions quiet_run(const std::filesystem::path& out) {
  RunOptions options;
  options.out = out;
  options.plot = false;
  options.report = nullptr;
  options.progress = nullptr;
  options.warnings = nullptr;
  return options;
}

// A valid scene: constant kernel, N = 64, t in (0, 2], cvode against the exact solution. Each member is
// the body of one section; set one to a bad value to test a message.
struct SceneText {
  std::string top = "name = \"fixture\"\n";
  std::string model = "kernel = { name = \"constant\" }\nlambda = 0.0\nsize = 64\n";
  std::string time = "end = 2.0\noutputs = [0.5, 1.0]\n";
  std::string engines = "[[engine]]\nname = \"cvode\"\nrtol = 1e-10\n\n[[engine]]\nname = \"exact\"\n";
  std::string observe = "series = [\"M0\", \"M1\", \"M2\"]\n";
  std::string compare = "reference = \"exact\"\ntolerance = { M0 = 1e-6, M2 = 1e-6 }\n";

  std::string text() const {
    std::string t = top + "\n[model]\n" + model + "\n[time]\n" + time + "\n" + engines + "\n[observe]\n" + observe;
    if (!compare.empty()) t += "\n[compare]\n" + compare;
    return t;
  }
};

// A scene with one bad input, the key its message must name and a piece of the value it must show.
struct BadScene {
  std::string description;
  std::string text;
  std::string key;
  std::string value;
  bool through_cli = false;  // also checked end to end through the `aggkit` binary
};

inline BadScene bad(std::string description, const std::function<void(SceneText&)>& change, std::string key,
                    std::string value, bool through_cli = false) {
  SceneText scene;
  change(scene);
  return {std::move(description), scene.text(), std::move(key), std::move(value), through_cli};
}

inline std::vector<BadScene> bad_scenes() {
  const bool cli = true;
  const std::string cvode = "[[engine]]\nname = \"cvode\"\n";
  return {
      // [model]
      bad("unknown tier", [](SceneText& s) { s.top = "name = \"fixture\"\ntier = \"slow\"\n"; }, "tier", "slow", cli),
      bad("negative lambda", [](SceneText& s) { s.model = "kernel = { name = \"constant\" }\nlambda = -0.5\nsize = 64\n"; }, "model.lambda", "-0.5", cli),
      bad("nan lambda", [](SceneText& s) { s.model = "kernel = { name = \"constant\" }\nlambda = nan\nsize = 64\n"; }, "model.lambda", "nan", cli),
      bad("lambda of the wrong type", [](SceneText& s) { s.model = "kernel = { name = \"constant\" }\nlambda = \"high\"\nsize = 64\n"; }, "model.lambda", "\"high\""),
      bad("lambda(t) turning negative", [](SceneText& s) { s.model = "kernel = { name = \"constant\" }\nlambda = { initial = 0.01, slope = -0.01 }\nsize = 64\n"; }, "model.lambda", "0.01"),
      bad("lambda table of unequal lengths", [](SceneText& s) { s.model = "kernel = { name = \"constant\" }\nlambda = { times = [0, 1], values = [0.1] }\nsize = 64\n"; }, "model.lambda.times", "2"),
      bad("lambda mixing forms", [](SceneText& s) { s.model = "kernel = { name = \"constant\" }\nlambda = { initial = 0.1, times = [0] }\nsize = 64\n"; }, "model.lambda", "initial"),
      bad("negative a", [](SceneText& s) { s.model = "kernel = { name = \"brownian\", a = -0.5 }\nsize = 64\n"; }, "model.kernel.a", "-0.5", cli),
      bad("a > 1", [](SceneText& s) { s.model = "kernel = { name = \"brownian\", a = 1.5 }\nsize = 64\n"; }, "model.kernel.a", "1.5", cli),
      bad("brownian without a", [](SceneText& s) { s.model = "kernel = { name = \"brownian\" }\nsize = 64\n"; }, "model.kernel.a", "missing"),
      bad("unknown kernel", [](SceneText& s) { s.model = "kernel = { name = \"gravity\" }\nsize = 64\n"; }, "model.kernel.name", "gravity", cli),
      bad("unknown kernel parameter", [](SceneText& s) { s.model = "kernel = { name = \"constant\", b = 2 }\nsize = 64\n"; }, "model.kernel.b", "2"),
      bad("kernel parameter of the wrong type", [](SceneText& s) { s.model = "kernel = { name = \"brownian\", a = \"big\" }\nsize = 64\n"; }, "model.kernel.a", "\"big\""),
      bad("negative mu", [](SceneText& s) { s.model = "kernel = { name = \"genproduct\", mu = -1 }\nsize = 64\n"; }, "model.kernel.mu", "-1"),
      bad("N < 2", [](SceneText& s) { s.model = "kernel = { name = \"constant\" }\nsize = 1\n"; }, "model.size", "1", cli),
      bad("negative N", [](SceneText& s) { s.model = "kernel = { name = \"constant\" }\nsize = -64\n"; }, "model.size", "-64"),
      bad("fractional N", [](SceneText& s) { s.model = "kernel = { name = \"constant\" }\nsize = 64.5\n"; }, "model.size", "64.5"),
      bad("missing N", [](SceneText& s) { s.model = "kernel = { name = \"constant\" }\n"; }, "model.size", "missing"),
      bad("unknown truncation", [](SceneText& s) { s.model += "truncation = \"clip\"\n"; }, "model.truncation", "clip"),
      bad("unknown initial kind", [](SceneText& s) { s.model += "initial = { kind = \"gaussian\" }\n"; }, "model.initial.kind", "gaussian"),
      bad("negative initial density", [](SceneText& s) { s.model += "initial = { kind = \"table\", n = [1.0, -0.25] }\n"; s.engines = "[[engine]]\nname = \"cvode\"\n"; s.compare = ""; }, "model.initial.n[1]", "-0.25"),
      bad("initial table longer than N", [](SceneText& s) { s.model = "kernel = { name = \"constant\" }\nsize = 2\ninitial = { kind = \"table\", n = [1, 0, 0] }\n"; s.engines = "[[engine]]\nname = \"cvode\"\n"; s.compare = ""; }, "model.initial.n", "3"),
      bad("zero monodisperse density", [](SceneText& s) { s.model += "initial = { kind = \"monodisperse\", density = 0 }\n"; }, "model.initial.density", "0"),
      bad("unknown grid scheme", [](SceneText& s) { s.model += "grid = { resolved = 16, ratio = 1.1, scheme = \"cell-average\" }\n"; }, "model.grid.scheme", "cell-average", cli),
      bad("unknown model key", [](SceneText& s) { s.model += "kernal = 1\n"; }, "model.kernal", "1", cli),
      // [time]
      bad("zero end time", [](SceneText& s) { s.time = "end = 0.0\n"; }, "time.end", "0"),
      bad("outputs not increasing", [](SceneText& s) { s.time = "end = 2.0\noutputs = [1.0, 0.5]\n"; }, "time.outputs[1]", "0.5"),
      bad("output after the end", [](SceneText& s) { s.time = "end = 2.0\noutputs = [3.0]\n"; }, "time.outputs[0]", "3"),
      bad("output at t = 0", [](SceneText& s) { s.time = "end = 2.0\noutputs = [0.0, 1.0]\n"; }, "time.outputs[0]", "0"),
      bad("outputs and every", [](SceneText& s) { s.time = "end = 2.0\noutputs = [1.0]\nevery = 0.5\n"; }, "time.every", "0.5"),
      bad("zero every", [](SceneText& s) { s.time = "end = 2.0\nevery = 0\n"; }, "time.every", "0"),
      bad("absurdly many outputs", [](SceneText& s) { s.time = "end = 2.0\nevery = 1e-9\n"; }, "time.every", "1e-09"),
      // [[engine]]
      bad("unknown engine", [](SceneText& s) { s.engines = "[[engine]]\nname = \"warp\"\n"; s.compare = ""; }, "engine[0].name", "warp", cli),
      bad("negative rtol", [cvode](SceneText& s) { s.engines = cvode + "rtol = -0.5\n"; s.compare = ""; }, "engine[0].rtol", "-0.5", cli),
      bad("zero rtol", [cvode](SceneText& s) { s.engines = cvode + "rtol = 0.0\n"; s.compare = ""; }, "engine[0].rtol", "0", cli),
      bad("nan atol", [cvode](SceneText& s) { s.engines = cvode + "atol = nan\n"; s.compare = ""; }, "engine[0].atol", "nan"),
      bad("unknown method", [cvode](SceneText& s) { s.engines = cvode + "method = \"rk4\"\n"; s.compare = ""; }, "engine[0].method", "rk4"),
      bad("unknown rhs", [cvode](SceneText& s) { s.engines = cvode + "rhs = \"slow\"\n"; s.compare = ""; }, "engine[0].rhs", "slow"),
      bad("negative krylov", [cvode](SceneText& s) { s.engines = cvode + "krylov = -3\n"; s.compare = ""; }, "engine[0].krylov", "-3"),
      bad("unknown preconditioner", [cvode](SceneText& s) { s.engines = cvode + "preconditioner = \"yes\"\n"; s.compare = ""; }, "engine[0].preconditioner", "\"yes\""),
      bad("dense Jacobian for large N", [cvode](SceneText& s) { s.model = "kernel = { name = \"constant\" }\nsize = 5000\n"; s.engines = cvode + "method = \"bdf-dense\"\n"; s.compare = ""; }, "engine[0].method", "bdf-dense"),
      bad("unknown engine key", [cvode](SceneText& s) { s.engines = cvode + "rtl = 1e-8\n"; s.compare = ""; }, "engine[0].rtl", "1e-08", cli),
      bad("duplicate engine labels", [cvode](SceneText& s) { s.engines = cvode + cvode; s.compare = ""; }, "engine[1].name", "cvode"),
      bad("label that is no folder name", [cvode](SceneText& s) { s.engines = cvode + "label = \"../x\"\n"; s.compare = ""; }, "engine[0].label", "../x"),
      bad("no engine", [](SceneText& s) { s.engines = ""; s.compare = ""; }, "engine", "missing"),
      bad("exact engine for the ballistic kernel", [](SceneText& s) { s.model = "kernel = { name = \"ballistic\" }\nsize = 64\n"; }, "model.kernel.name", "ballistic"),
      bad("exact engine with shattering", [](SceneText& s) { s.model = "kernel = { name = \"constant\" }\nlambda = 0.01\nsize = 64\n"; }, "model.lambda", "0.01"),
      bad("exact engine past gelation", [](SceneText& s) { s.model = "kernel = { name = \"product\" }\nsize = 64\n"; }, "time.end", "2"),
      bad("exact engine from a table", [](SceneText& s) { s.model += "initial = { kind = \"table\", n = [1.0] }\n"; }, "model.initial.kind", "table"),
      bad("exact engine with density 2", [](SceneText& s) { s.model += "initial = { kind = \"monodisperse\", density = 2.0 }\n"; }, "model.initial.density", "2"),
      // [observe]
      bad("negative moment order", [](SceneText& s) { s.observe = "series = [\"M0\", \"M-1\"]\n"; }, "observe.series[1]", "M-1"),
      bad("unknown observable", [](SceneText& s) { s.observe = "series = [\"energy\"]\n"; s.compare = ""; }, "observe.series[0]", "energy"),
      bad("density beyond N", [](SceneText& s) { s.observe = "series = [\"n65\"]\n"; s.compare = ""; }, "observe.series[0]", "n65"),
      bad("observable twice", [](SceneText& s) { s.observe = "series = [\"M0\", \"M0\"]\n"; }, "observe.series[1]", "M0"),
      bad("empty series", [](SceneText& s) { s.observe = "series = []\n"; s.compare = ""; }, "observe.series", "[]"),
      bad("distribution at no output time", [](SceneText& s) { s.observe += "distributions = [0.75]\n"; }, "observe.distributions[0]", "0.75"),
      bad("series measure of an unobserved series", [](SceneText& s) { s.time = "end = 40.0\nevery = 1.0\n"; s.observe += "final = [\"oscillation_period:M3\"]\n"; }, "observe.final[0]", "oscillation_period:M3"),
      bad("final-configuration observable without particles", [](SceneText& s) { s.observe += "final = [\"contacts\"]\n"; }, "observe.final[0]", "contacts"),
      bad("series measure over too few output times", [](SceneText& s) { s.observe += "final = [\"oscillation_period:M0\"]\n"; }, "observe.final", "2 output times"),
      bad("series measure over unevenly spaced times", [](SceneText& s) { s.time = "end = 40.0\noutputs = [" + [] { std::string t; for (int i = 1; i <= 19; ++i) t += std::to_string(i) + ".0, "; return t; }() + "30.0]\n"; s.observe += "final = [\"oscillation_period:M0\"]\nwindow = [0.0, 40.0]\n"; }, "observe.window", "[0, 40]"),
      bad("distribution tolerance without distributions", [](SceneText& s) { s.compare += "distribution = 0.01\n"; }, "compare.distribution", "none are observed"),
      bad("window beyond the end", [](SceneText& s) { s.observe += "window = [1.0, 3.0]\n"; }, "observe.window", "[1, 3]"),
      // [compare]
      bad("unknown reference", [](SceneText& s) { s.compare = "reference = \"dsmc\"\n"; }, "compare.reference", "dsmc"),
      bad("negative tolerance", [](SceneText& s) { s.compare = "reference = \"exact\"\ntolerance = { M0 = -0.1 }\n"; }, "compare.tolerance.M0", "-0.1"),
      bad("tolerance for an unobserved quantity", [](SceneText& s) { s.compare = "reference = \"exact\"\ntolerance = { M3 = 0.1 }\n"; }, "compare.tolerance.M3", "0.1"),
      bad("comparison with one engine", [](SceneText& s) { s.engines = "[[engine]]\nname = \"exact\"\n"; }, "compare.reference", "exact"),
      // structure
      bad("unknown top-level key", [](SceneText& s) { s.top += "colour = \"blue\"\n"; }, "colour", "blue", cli),
      bad("unknown key in [time]", [](SceneText& s) { s.time += "start = 0.0\n"; }, "time.start", "0"),
      bad("missing name", [](SceneText& s) { s.top = ""; }, "name", "missing"),
      bad("malformed TOML", [](SceneText& s) { s.model += "size = [1,\n"; }, "scene", "malformed TOML", cli),
  };
}

// A fresh, empty folder under the test scratch folder.
inline std::filesystem::path scratch_folder(const std::string& name) {
  const std::filesystem::path folder = std::filesystem::path(AGGKIT_TEST_TMP) / name;
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

inline std::filesystem::path write_text(const std::filesystem::path& file, const std::string& text) {
  std::filesystem::create_directories(file.parent_path());
  std::ofstream(file) << text;
  return file;
}

inline std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

inline std::string first_line(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

// Files under `folder` whose name is `name` (searched recursively).
// Rows of a CSV file after its header, as numbers.
inline std::vector<std::vector<double>> csv_rows(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

inline int count_files_named(const std::filesystem::path& folder, const std::string& name) {
  int count = 0;
  if (!std::filesystem::exists(folder)) return 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder))
    if (entry.path().filename() == name) ++count;
  return count;
}

inline std::filesystem::path shipped_scene(const std::string& name) {
  return std::filesystem::path(AGGKIT_SOURCE_DIR) / "validation" / "scenes" / name;
}

}  // namespace aggkit::testing

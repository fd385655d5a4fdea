// `mpirun -np K aggkit run SCENE`: the realizations of the particle engines and the runs of DSMC spread over
// the ranks give the files of a one-process run with the same seeds, byte for byte (final.json but for its
// wall-clock entries): rank 0 gathers every realization's results and reduces them in realization order as one
// process does. More ranks than realizations leave ranks idle. A bad scene ends every rank with exit status 2
// (no rank left waiting), deterministic engines run on rank 0 alone, and checkpoints, which one process writes, are refused under several ranks.
#include <catch2/catch.hpp>

#include <filesystem>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "tests/apps/command_fixture.hpp"
#include "tests/validation/scene_fixture.hpp"

using aggkit::testing::quoted;
using aggkit::testing::read_text;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

// ED, 5 realizations on 2 threads of each rank (rank 0 runs 0, 2, 4; rank 1 runs 1, 3): about 1 s in all.
// The snapshot, trajectory and pair distribution come from realization 0 (rank 0) or from all of them.
const char* ed_scene = R"(name = "mpi-ed"
[particles]
dimension = 2
count = 900
radius = 0.2
volume_fraction = 0.2
boundary = "reflecting"
initial = { lattice = "square", speed = 1.0, directions = "uniform" }
seed = 5
realizations = 5
[time]
end = 10.0
every = 0.5
[[engine]]
name = "ed"
threads = 2
[observe]
series = ["clusters", "kinetic_energy", "M2"]
final = ["clusters", "contacts", "pair_distribution"]
snapshots = { every = 5.0 }
)";

// DSMC, 3 runs (rank 2 of 4 runs 2, rank 3 none), distributions at two times; with a CVODE engine that runs
// on rank 0 alone and the comparison of the two.
const char* dsmc_scene = R"(name = "mpi-dsmc"
[model]
kernel = { name = "ballistic" }
lambda = 0.01
size = 500
truncation = "drop"
initial = { kind = "monodisperse" }
[time]
end = 5.0
every = 0.25
[[engine]]
name = "dsmc"
particles = 3000
runs = 3
seed = 77
threads = 2
[[engine]]
name = "cvode"
[observe]
series = ["M0", "M2", "M3"]
distributions = [2.5, 5.0]
[compare]
reference = "cvode"
tolerance = { M0 = { relative = 0.05, stderr = 5 } }
)";

using Outcome = aggkit::testing::CommandOutcome;

Outcome run_scene(const std::string& prefix, const fs::path& scene, const fs::path& out, const std::string& more = "") {
  return aggkit::testing::run_command(prefix + quoted(AGGKIT_CLI) + " run " + quoted(scene.string()) + " --out " +
                                          quoted(out.string()) + " --no-plot " + more,
                                      out.parent_path());
}

// final.json without its wall-clock entries (which differ between any two runs).
std::string without_wall_time(const fs::path& file) {
  return std::regex_replace(read_text(file), std::regex("\\s*\"wall_seconds(_stderr)?\": [^\\n]*\\n"), "\n");
}

// The files under `folder`, relative to it.
std::set<std::string> files_in(const fs::path& folder) {
  std::set<std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) files.insert(fs::relative(entry.path(), folder).string());
  return files;
}

// Every file of the one-process run `single` is in `spread` with the same bytes (final.json: but for
// wall_seconds; summary.json holds timings and the rank count); `spread` has no other file.
void check_same_outputs(const fs::path& single, const fs::path& spread) {
  const std::set<std::string> files = files_in(single);
  CHECK(files == files_in(spread));
  for (const std::string& file : files) {
    INFO(file);
    if (fs::path(file).filename() == "summary.json") continue;
    if (fs::path(file).filename() == "final.json") CHECK(without_wall_time(single / file) == without_wall_time(spread / file));
    else CHECK(read_text(single / file) == read_text(spread / file));
  }
}

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("run cli: mpirun -np 2 spreads the ED realizations and writes the files of one process", "[mpi]") {
  const auto folder = aggkit::testing::scratch_folder("run-mpi-ed");
  const auto scene = aggkit::testing::write_text(folder / "scene.toml", ed_scene);
  const Outcome single = run_scene("", scene, folder / "single");
  INFO(single.err);
  REQUIRE(single.exit_code == 0);
  const Outcome two = run_scene(aggkit::testing::mpirun(2), scene, folder / "two");
  INFO(two.err);
  REQUIRE(two.exit_code == 0);
  REQUIRE(fs::exists(folder / "two" / "ed" / "series.csv"));
  REQUIRE(fs::exists(folder / "two" / "ed" / "final.json"));
  REQUIRE(fs::exists(folder / "two" / "ed" / "final.vtu"));
  check_same_outputs(folder / "single", folder / "two");
  CHECK_THAT(read_text(folder / "two" / "summary.json"), Contains("\"ranks\": 2"));
  // Progress from rank 0 only. Progress lines appear only once a run has taken longer than a second (and
  // "done" only after one of them), so how many there are depends on the machine's load; what does not is
  // that no second rank repeats rank 0's "done" line.
  CHECK(occurrences(two.err, "engine 1/1 ed: done in") <= 1);
}

TEST_CASE("run cli: mpirun spreads the DSMC runs, with idle ranks when there are more ranks than runs", "[mpi]") {
  const auto folder = aggkit::testing::scratch_folder("run-mpi-dsmc");
  const auto scene = aggkit::testing::write_text(folder / "scene.toml", dsmc_scene);
  const Outcome single = run_scene("", scene, folder / "single");
  INFO(single.err);
  REQUIRE(single.exit_code == 0);
  for (int ranks : {2, 4}) {
    const fs::path out = folder / ("np" + std::to_string(ranks));
    const Outcome spread = run_scene(aggkit::testing::mpirun(ranks), scene, out);
    INFO(ranks << " ranks: " << spread.err);
    REQUIRE(spread.exit_code == 0);
    REQUIRE(fs::exists(out / "dsmc" / "series.csv"));
    REQUIRE(fs::exists(out / "dsmc" / "distribution.csv"));
    check_same_outputs(folder / "single", out);
    CHECK_THAT(read_text(out / "summary.json"), Contains("\"ranks\": " + std::to_string(ranks)));
  }
}

TEST_CASE("run cli: under mpirun the deterministic engines (snes, cvode) run on rank 0 alone", "[mpi]") {
  // PETSc on rank 0 alone: its initialisation must not wait for the other ranks, which wait for rank 0.
  const auto folder = aggkit::testing::scratch_folder("run-mpi-snes");
  const fs::path scene = fs::path(AGGKIT_SOURCE_DIR) / "validation" / "scenes" / "brownian-steady.toml";
  const Outcome single = run_scene("", scene, folder / "single");
  INFO(single.err);
  REQUIRE(single.exit_code == 0);
  const Outcome two = run_scene(aggkit::testing::mpirun(2), scene, folder / "two");
  INFO(two.err);
  REQUIRE(two.exit_code == 0);
  check_same_outputs(folder / "single", folder / "two");
}

TEST_CASE("run cli: under mpirun a bad scene ends every rank with exit 2, and checkpoints are refused", "[mpi]") {
  const auto folder = aggkit::testing::scratch_folder("run-mpi-refused");
  std::string bad = dsmc_scene;
  bad.replace(bad.find("runs = 3"), 8, "runs = -3");
  const auto bad_scene = aggkit::testing::write_text(folder / "bad.toml", bad);
  const Outcome refused = run_scene(aggkit::testing::mpirun(2), bad_scene, folder / "bad");
  INFO(refused.err);
  CHECK(refused.exit_code == 2);
  CHECK(occurrences(refused.err, "aggkit: error: engine[0].runs") == 1);  // said once, by rank 0
  CHECK_FALSE(fs::exists(folder / "bad" / "summary.json"));

  const auto scene = aggkit::testing::write_text(folder / "scene.toml", dsmc_scene);
  const Outcome every = run_scene(aggkit::testing::mpirun(2), scene, folder / "every", "--checkpoint-every 10");
  INFO(every.err);
  CHECK(every.exit_code == 2);
  CHECK_THAT(every.err, Contains("--checkpoint-every = 10: checkpoints with one process only"));

  std::string own = ed_scene;
  own.replace(own.find("threads = 2"), 11, "threads = 2\ncheckpoint_every = 60");
  const auto own_scene = aggkit::testing::write_text(folder / "own.toml", own);
  const Outcome option = run_scene(aggkit::testing::mpirun(2), own_scene, folder / "own");
  INFO(option.err);
  CHECK(option.exit_code == 2);
  CHECK_THAT(option.err, Contains("engine[0].checkpoint_every = 60: checkpoints with one process only"));
}

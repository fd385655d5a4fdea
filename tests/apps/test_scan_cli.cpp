// `aggkit scan` end to end: the same CSV from one process and from `mpirun -np 2`, resumption after an
// interruption without recomputing finished points, the phase diagram, and bad input (exit 2). The cycles
// continued down the columns: tests/apps/test_scan_columns.cpp.
#include <catch2/catch.hpp>

#include <cmath>

#include <algorithm>
#include <chrono>
#include <map>
#include <sstream>
#include <cstdlib>
#include <sys/wait.h>
#include <thread>
#include <utility>
#include <vector>

#include "tests/apps/command_fixture.hpp"
#include "tests/apps/scan_cli_fixture.hpp"
#include "tests/validation/scene_fixture.hpp"

using Catch::Matchers::Contains;
namespace fs = std::filesystem;

using namespace aggkit::testing::scan;
using aggkit::testing::quoted;

namespace {

// 3 x 3 points at N = 128 (cutoff: mass conserved), t up to 100: steady, damped and monotone regimes, each
// point a few hundredths of a second.
const char* const small_scan = R"(
name = "small-scan"
[model]
kernel = { name = "brownian", a = 0.9 }
size = 128
truncation = "cutoff"
[time]
end = 100.0
every = 1.0
[scan]
a = { from = 0.6, to = 0.9, count = 3 }
lambda = { from = 0.01, to = 1.0, count = 3, spacing = "log" }
)";

std::map<std::string, std::string> point_files(const fs::path& out) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::directory_iterator(out / "points"))
    // Grid points only: the scan also keeps hopf_*.csv and cycle_column_* files and the refined repeats
    // (*_refined.csv).
    if (const std::string name = entry.path().filename().string();
        entry.path().extension() == ".csv" && !name.starts_with("hopf") && !name.starts_with("cycle_column") &&
        !name.ends_with("_refined.csv"))
      files[entry.path().filename().string()] = aggkit::testing::read_text(entry.path());
  return files;
}

std::size_t lines(const std::string& text) { return std::size_t(std::count(text.begin(), text.end(), '\n')); }

}  // namespace

TEST_CASE("scan cli: one process and mpirun -np 2 write the same scan.csv and lambda_crit.csv", "[mpi]") {
  const auto folder = aggkit::testing::scratch_folder("scan-cli-mpi");
  const auto scene = aggkit::testing::write_text(folder / "scan.toml", small_scan);
  const Outcome single = run(scan_command("", scene, folder / "single"), folder);
  REQUIRE(single.exit_code == 0);
  const Outcome two = run(scan_command(mpirun(2), scene, folder / "two"), folder);
  INFO(two.err);
  REQUIRE(two.exit_code == 0);
  const std::string csv = aggkit::testing::read_text(folder / "single" / "scan.csv");
  CHECK(lines(csv) == 10);  // header + 9 points
  CHECK(aggkit::testing::first_line(folder / "single" / "scan.csv").rfind("a,lambda,regime,period,amplitude,", 0) == 0);
  CHECK(csv == aggkit::testing::read_text(folder / "two" / "scan.csv"));
  CHECK(aggkit::testing::read_text(folder / "single" / "lambda_crit.csv") ==
        aggkit::testing::read_text(folder / "two" / "lambda_crit.csv"));
  CHECK(aggkit::testing::first_line(folder / "two" / "lambda_crit.csv").rfind("a,lambda_crit,", 0) == 0);
  // Both ranks computed points.
  const std::string timing = aggkit::testing::read_text(folder / "two" / "timing.csv");
  CHECK_THAT(timing, Contains(",0\n") && Contains(",1\n"));
  CHECK_THAT(two.err, Contains("[rank 1]"));
}

TEST_CASE("scan cli: an interrupted scan resumes without recomputing its finished points") {
  const auto folder = aggkit::testing::scratch_folder("scan-cli-resume");
  const auto scene = aggkit::testing::write_text(folder / "scan.toml", small_scan);
  const auto out = folder / "out";
  REQUIRE(run(scan_command("", scene, out), folder).exit_code == 0);
  const std::string complete = aggkit::testing::read_text(out / "scan.csv");
  auto before = point_files(out);
  REQUIRE(before.size() == 9);

  // Interrupted: two points lost, scan.csv not yet written, a half-written point file left behind.
  const std::string lost1 = before.begin()->first, lost2 = std::next(before.begin(), 4)->first;
  fs::remove(out / "points" / lost1);
  fs::remove(out / "points" / lost2);
  fs::remove(out / "scan.csv");
  aggkit::testing::write_text(out / "points" / (lost1 + ".partial"), "a,lambda,regime\n0.6,");
  const Outcome resumed = run(scan_command("", scene, out, /*plot=*/true), folder);
  INFO(resumed.err);
  REQUIRE(resumed.exit_code == 0);
  CHECK_THAT(resumed.err, Contains("9 runs, 7 finished earlier, 2 to compute"));
  // Progress lines continue the count after the 7 finished runs, and a relaxing point prints no "period nan".
  CHECK_THAT(resumed.err, Contains(" 8/9 a = ") && Contains(" 9/9 a = "));
  CHECK(resumed.err.find(" 1/2 ") == std::string::npos);
  std::istringstream progress_lines(resumed.err);
  for (std::string line; std::getline(progress_lines, line);)
    if (line.find("/9 a = ") != std::string::npos) CHECK(line.find("nan") == std::string::npos);
  const auto after = point_files(out);
  REQUIRE(after.size() == 9);
  // Finished points were not recomputed: their files (with the wall time of their run) are unchanged.
  for (const auto& [name, text] : before)
    if (name != lost1 && name != lost2) CHECK(after.at(name) == text);
  CHECK(aggkit::testing::read_text(out / "scan.csv") == complete);
  // The phase diagram is a PNG.
  CHECK(aggkit::testing::read_text(out / "phase_diagram.png").substr(1, 3) == "PNG");

  // A damaged cached Hopf point (e.g. a disk filled mid-write) is computed again with a warning, not a crash.
  bool damaged = false;
  for (const auto& entry : fs::directory_iterator(out / "points"))
    if (entry.path().filename().string().starts_with("hopf_") && !damaged) {
      aggkit::testing::write_text(entry.path(), "a,found,lambda_crit,lambda_tolerance,omega,note\n0.6,yes,zz,1e-3,0.1,\n");
      damaged = true;
    }
  REQUIRE(damaged);  // the scan keeps its Hopf points in points/ (stability analysis is always built)
  {
    fs::remove(out / "scan.csv");
    const Outcome repaired = run(scan_command("", scene, out), folder);
    INFO(repaired.err);
    CHECK(repaired.exit_code == 0);
    CHECK_THAT(repaired.err, Contains("is damaged; computing that point again"));
    CHECK(aggkit::testing::read_text(out / "scan.csv") == complete);
  }

  // A changed scene (here the time grid) does not reuse the old points.
  const auto changed = aggkit::testing::write_text(folder / "changed.toml",
                                                   std::string(small_scan).replace(std::string(small_scan).find("end = 100.0"), 11, "end = 90.0"));
  const Outcome rerun = run(scan_command("", changed, out), folder);
  REQUIRE(rerun.exit_code == 0);
  CHECK_THAT(rerun.err, Contains("earlier results discarded") && Contains("0 finished earlier, 9 to compute"));
}

TEST_CASE("scan cli: a scan killed while running continues from its finished points") {
  const auto folder = aggkit::testing::scratch_folder("scan-cli-kill");
  // 8 points of ~0.1-0.5 s (N = 512): long enough to be killed midway.
  std::string text = small_scan;
  text.replace(text.find("size = 128"), 10, "size = 512");
  text.replace(text.find("end = 100.0"), 11, "end = 400.0");
  text.replace(text.find("count = 3 }\nlambda"), 9, "count = 2");
  text.replace(text.find("count = 3, spacing"), 9, "count = 4");
  const auto scene = aggkit::testing::write_text(folder / "scan.toml", text);
  const auto out = folder / "out";
  const auto pid_file = folder / "pid";
  std::system((scan_command("", scene, out) + " >/dev/null 2>" + quoted((folder / "kill.txt").string()) + " & echo $! > " + quoted(pid_file.string())).c_str());
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  std::size_t finished = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    if (fs::exists(out / "points")) finished = point_files(out).size();
    if (finished >= 1) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  INFO(aggkit::testing::read_text(folder / "kill.txt"));
  REQUIRE(finished >= 1);
  std::system(("kill -KILL $(cat " + quoted(pid_file.string()) + ") 2>/dev/null; sleep 0.2").c_str());
  const auto survivors = point_files(out);
  const Outcome resumed = run(scan_command("", scene, out), folder);
  INFO(resumed.err);
  REQUIRE(resumed.exit_code == 0);
  CHECK_THAT(resumed.err, Contains("8 runs, " + std::to_string(survivors.size()) + " finished earlier"));
  const auto after = point_files(out);
  CHECK(after.size() == 8);
  for (const auto& [name, content] : survivors) CHECK(after.at(name) == content);
  CHECK(lines(aggkit::testing::read_text(out / "scan.csv")) == 9);
}

TEST_CASE("scan cli: the truncation check repeats points and the lambda_crit bracket at 2N") {
  const auto folder = aggkit::testing::scratch_folder("scan-cli-truncation");
  // λ grid 0.01, 0.1, 1 at a = 0.9; a synthetic bracket is not needed: the check points are listed.
  std::string text = small_scan;
  text += "truncation_check = { points = [[0.9, 0.1], [0.75, 0.05]], lambda_crit = true }\n";
  const auto scene = aggkit::testing::write_text(folder / "scan.toml", text);
  const Outcome outcome = run(scan_command("", scene, folder / "out"), folder);
  INFO(outcome.err);
  REQUIRE(outcome.exit_code == 0);
  const std::string check = aggkit::testing::read_text(folder / "out" / "truncation_check.csv");
  CHECK(check.rfind("a,lambda,N,regime,period,amplitude,regime_2N,period_2N,amplitude_2N,period_change,amplitude_change\n", 0) == 0);
  CHECK(lines(check) == 3);
  CHECK_THAT(check, Contains("0.9,0.1,128,") && Contains("0.75,0.05,128,"));
  // (0.9, 0.1) is a grid point: its N = 128 run is the grid's (one file), and its 2N run exists.
  CHECK(fs::exists(folder / "out" / "points" / "a0.9_lambda0.1_N128.csv"));
  CHECK(fs::exists(folder / "out" / "points" / "a0.9_lambda0.1_N256.csv"));
  CHECK_THAT(outcome.err, Contains("12 runs"));  // 9 grid points, (0.9, 0.1) at 2N, (0.75, 0.05) at N and 2N
}

TEST_CASE("scan cli: bad input exits 2 naming the key and the value") {
  const auto folder = aggkit::testing::scratch_folder("scan-cli-bad");
  const auto replace = [](std::string text, const std::string& from, const std::string& to) {
    return text.replace(text.find(from), from.size(), to);
  };
  struct Case {
    std::string text, key, value;
  };
  const std::vector<Case> cases{
      {replace(small_scan, "from = 0.6, to = 0.9", "from = 0.6, to = 1.5"), "scan.a[1]", "1.05"},
      {replace(small_scan, "from = 0.01, to = 1.0", "from = 1.0, to = 0.01"), "scan.lambda.to", "0.01"},
      {replace(small_scan, "count = 3, spacing", "count = 0, spacing"), "scan.lambda.count", "0"},
      {replace(small_scan, "from = 0.01, to = 1.0", "from = -0.01, to = 1.0"), "scan.lambda.from", "-0.01"},
      {small_scan + std::string("cycle_run = -5\n"), "scan.cycle_run", "-5"},
      {small_scan + std::string("cycles = 3\n"), "scan.cycles", "3"},
      {small_scan + std::string("cycle_column = 4\n"), "scan.cycle_column", "4"},
      {small_scan + std::string("series = \"M2\"\ncycle_column = 12\n"), "scan.cycle_column", "12"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    INFO(cases[i].text);
    const auto scene = aggkit::testing::write_text(folder / ("bad" + std::to_string(i) + ".toml"), cases[i].text);
    const Outcome bad = run(scan_command("", scene, folder / "out"), folder);
    CHECK(bad.exit_code == 2);
    CHECK_THAT(bad.err, Contains("aggkit: error: " + cases[i].key) && Contains(cases[i].value));
  }
  CHECK_FALSE(fs::exists(folder / "out"));
  // An output folder that cannot be created (its parent is a file), also under mpirun.
  const auto scene = aggkit::testing::write_text(folder / "good.toml", small_scan);
  aggkit::testing::write_text(folder / "file", "not a folder");
  const Outcome unwritable = run(scan_command("", scene, folder / "file" / "out"), folder);
  CHECK(unwritable.exit_code == 2);
  CHECK_THAT(unwritable.err, Contains("--out") && Contains("file/out"));
  const Outcome unwritable_mpi = run(scan_command(mpirun(2), scene, folder / "file" / "out"), folder);
  CHECK(unwritable_mpi.exit_code == 2);
  CHECK_THAT(unwritable_mpi.err, Contains("--out"));
}

namespace {
// The Hopf bifurcation's criticality on the coarse scan's own grid: its crossing lies between the unstable
// (0.9, 0.001) and the stable (0.9, 0.004) of this grid (0.0027, far from the converged 0.0096), and the first
// Lyapunov coefficient there is negative: supercritical, as on the converged grid (bench/results/RESULTS.md).
void check_coarse_criticality(const fs::path& out) {
  const auto crit_rows = aggkit::testing::read_csv(out / "lambda_crit.csv");
  REQUIRE(crit_rows.size() == 2);
  for (const auto& row : crit_rows) {
    INFO("a = " << row.at("a") << ": " << row.at("note"));
    CHECK(row.at("criticality") == "supercritical");
    CHECK(std::stod(row.at("lyapunov")) < 0);
    CHECK(std::stod(row.at("m0_half_range_predicted")) > 0);
    if (row.at("a") == "0.9") {
      CHECK(std::stod(row.at("lambda_crit_scan_grid")) > 0.001);
      CHECK(std::stod(row.at("lambda_crit_scan_grid")) < 0.004);
    }
  }
  CHECK(fs::exists(out / "points" / "hopf_criticality_a0.9_N1048576.csv"));  // what a resumed scan reads
}
}  // namespace

TEST_CASE("scan cli: a relaxing point that does not relax on the refined grid is unresolved") {
  const auto folder = aggkit::testing::scratch_folder("scan-cli-refine");
  const auto scene = aggkit::testing::write_text(folder / "scan.toml", coarse_scan);
  const Outcome outcome = run(scan_command("", scene, folder / "out"), folder);
  INFO(outcome.err);
  REQUIRE(outcome.exit_code == 0);
  const fs::path csv = folder / "out" / "scan.csv";
  CHECK_THAT(aggkit::testing::first_line(csv), Contains(",note,mean_steady,regime_refined"));
  const auto low = scan_row(csv, 0.9, 0.004);
  REQUIRE(!low.empty());
  CHECK(low.at("regime") == "unresolved");
  CHECK(!low.at("regime_refined").empty());
  CHECK_THAT(low.at("note"), Contains("was damped in the run; on the refined grid (N = 2097152; graded(K=8; r=1.3") &&
                                 Contains("with an unstable steady state (Re mu = "));
  CHECK(fs::exists(folder / "out" / "points" / "a0.9_lambda0.004_N2097152_refined.csv"));
  const auto high = scan_row(csv, 0.9, 0.012);  // relaxes on both grids: keeps its verdict
  CHECK((high.at("regime") == "damped" || high.at("regime") == "steady"));
  CHECK((high.at("regime_refined") == "damped" || high.at("regime_refined") == "steady"));
  // Only relaxing verdicts are repeated: (0.9, 0.001) oscillates on the coarse grid already.
  const auto sustained = scan_row(csv, 0.9, 0.001);
  CHECK(sustained.at("regime") == "sustained");
  CHECK(sustained.at("regime_refined").empty());
  CHECK(!fs::exists(folder / "out" / "points" / "a0.9_lambda0.001_N2097152_refined.csv"));

  check_coarse_criticality(folder / "out");

  // Every point has a steady state reached by continuation from λ = 0.1 and a converged spectrum; the verdict
  // comes from the spectrum and the cycle, the run confirming: (0.9, 0.001) unstable, oscillating in the run and
  // with a stable cycle: sustained; (0.85, 0.001) unstable, the run too short to show a cycle (one period in its
  // tail) but shooting finds a stable one (period 183): sustained; (0.9, 0.012) a stable focus: damped (the run
  // agrees); (0.9, 0.004) stable on the coarse grid but unstable on the refined one: unresolved, said so.
  CHECK_THAT(aggkit::testing::first_line(csv), Contains(",steady_how,spectrum_converged,verdict"));
  for (const auto& row : aggkit::testing::read_csv(csv)) {
    INFO(row.at("a") << ", " << row.at("lambda"));
    CHECK(row.at("spectrum_converged") == "yes");
    CHECK_THAT(row.at("steady_how"), Contains("continuation from lambda = 0.1 in "));
    CHECK(!row.at("verdict").empty());
  }
  CHECK(sustained.at("verdict") == "sustained");
  const auto slow = scan_row(csv, 0.85, 0.001);
  CHECK(slow.at("regime") == "unresolved");
  CHECK(slow.at("verdict") == "sustained");
  CHECK(slow.at("cycle_stable") == "yes");
  CHECK(std::stod(slow.at("floquet_max")) < 1.0);
  CHECK(std::stod(slow.at("cycle_m0_min")) < std::stod(slow.at("cycle_m0_max")));
  CHECK(sustained.at("cycle_stable") == "yes");
  CHECK(std::isnan(std::stod(high.at("cycle_period"))));  // no cycle around a stable focus

  CHECK(high.at("verdict") == "damped");
  CHECK(high.at("agree") == "yes");
  CHECK(low.at("verdict") == "unresolved");
  CHECK_THAT(low.at("note"), Contains("the spectrum's verdict damped is not kept: the refined grid's steady state is unstable"));

  // Without refinement the coarse grid's verdict stands, from the same grid runs (refine is not part of
  // the fingerprint: nothing is recomputed).
  std::string plain = coarse_scan;
  plain += "refine = false\n";
  const auto unrefined = aggkit::testing::write_text(folder / "plain.toml", plain);
  const Outcome again = run(scan_command("", unrefined, folder / "out"), folder);
  INFO(again.err);
  REQUIRE(again.exit_code == 0);
  CHECK_THAT(again.err, Contains("7 runs, 7 finished earlier, 0 to compute"));  // 6 points and the Hopf curve
  CHECK(scan_row(csv, 0.9, 0.004).at("regime") == "damped");
  CHECK(scan_row(csv, 0.9, 0.004).at("regime_refined").empty());
}

TEST_CASE("scan cli: a run budget too short to reach the cycle leaves the point unstable and says why") {
  // cycle_run = 100, below the scene's own t_end: no cycle is sought at (0.85, 0.001), whose run shows none.
  const auto folder = aggkit::testing::scratch_folder("scan-cli-budget");
  const auto budget = aggkit::testing::write_text(folder / "budget.toml", std::string(coarse_scan) + "refine = false\ncycle_run = 100\n");
  const Outcome budgeted = run(scan_command("", budget, folder / "budget"), folder);
  INFO(budgeted.err);
  REQUIRE(budgeted.exit_code == 0);
  const auto unsought = scan_row(folder / "budget" / "scan.csv", 0.85, 0.001);
  CHECK(unsought.at("verdict") == "unstable");
  CHECK(unsought.at("cycle_stable").empty());
  CHECK_THAT(unsought.at("note"), Contains("no cycle sought") && Contains("beyond cycle_run = 100"));
}

TEST_CASE("scan cli: the converged Hopf curve runs beside the columns, with the same results on 2 ranks", "[mpi]") {
  const auto folder = aggkit::testing::scratch_folder("scan-cli-curve-mpi");
  // With the cycles continued down the columns too: one column per a, each walked by one rank, and the curve
  // then beside the columns (the points come after them).
  const auto scene = aggkit::testing::write_text(folder / "scan.toml", std::string(coarse_scan) + "cycle_column = 12\n");
  const Outcome single = run(scan_command("", scene, folder / "single"), folder);
  REQUIRE(single.exit_code == 0);
  const Outcome two = run(scan_command(mpirun(2), scene, folder / "two"), folder);
  INFO(two.err);
  REQUIRE(two.exit_code == 0);
  CHECK_THAT(two.err, Contains("continued down 2 columns of lambda, and the converged Hopf curve: 3 runs") &&
                          Contains("grid of 2 a x 3 lambda at N = 1048576: 6 runs"));
  for (const char* file : {"scan.csv", "lambda_crit.csv"})
    CHECK(aggkit::testing::read_text(folder / "single" / file) == aggkit::testing::read_text(folder / "two" / file));
  CHECK_THAT(aggkit::testing::read_text(folder / "two" / "lambda_crit.csv"), Contains("hopf-converged"));

  // A damaged cached point of the curve (a disk filled mid-write) is computed again, to the same value within
  // its bracket (the resumed continuation starts from a = 0.9's cached value, not from the path to it).
  const fs::path cached = folder / "single" / "points" / "hopfcurve_a0.85_K8_r1.6_fixed-pivot.csv";
  REQUIRE(fs::exists(cached));
  std::string text = aggkit::testing::read_text(cached);
  const std::size_t value = text.find(',', text.find("\n0.85,") + 6) + 1;  // λ_crit, after a and converged
  text.replace(value, text.find(',', value) - value, "0.00zz");
  aggkit::testing::write_text(cached, text);
  fs::remove(folder / "single" / "lambda_crit.csv");
  const Outcome repaired = run(scan_command("", scene, folder / "single"), folder);
  INFO(repaired.err);
  REQUIRE(repaired.exit_code == 0);
  CHECK_THAT(repaired.err, Contains("converging lambda_crit(a)") && Contains("for 1 values of a"));
  const auto crit = [](const fs::path& csv) {
    for (const auto& row : aggkit::testing::read_csv(csv))
      if (row.at("a") == "0.85") return std::stod(row.at("lambda_crit"));
    return 0.0;
  };
  const double again = crit(folder / "single" / "lambda_crit.csv"), before = crit(folder / "two" / "lambda_crit.csv");
  CHECK(before > 0);
  CHECK(again == Approx(before).epsilon(1e-4));  // the bracket: 8.5e-8 of 0.00157 (5e-5)
}

TEST_CASE("scan cli: where the grid's roots go negative the steady state is sought on the refined grid") {
  // a = 0.7 on K = 16, r = 1.1 up to N = 2^34 with three-moment shares (four-moment ones have positive roots
  // down to 1e-9 here): the continuation's roots go negative below λ = 7.5e-6 on this grid, below 2.8e-6 on
  // the refined one (r = 1.05). At λ = 4e-6 the refined grid's steady state (unstable:
  // λ_crit(0.7) = 4.4e-4) decides the point; at 1e-9 neither grid has a positive root, and the row says where
  // each walk stopped. Runs to t = 10 only (the verdict comes from the spectrum; no cycles).
  const auto folder = aggkit::testing::scratch_folder("scan-cli-negative");
  const auto scene = aggkit::testing::write_text(folder / "scan.toml", R"(
name = "negative-roots"
[model]
kernel = { name = "brownian", a = 0.7 }
size = 17179869184
grid = { resolved = 16, ratio = 1.1, scheme = "three-moment" }
[time]
end = 10.0
every = 0.25
[scan]
a = [0.7]
lambda = [1e-9, 4e-6]
refine = false
cycles = false
)");
  const Outcome outcome = run(scan_command("", scene, folder / "out", /*plot=*/true), folder);
  INFO(outcome.err);
  REQUIRE(outcome.exit_code == 0);
  const fs::path csv = folder / "out" / "scan.csv";
  const auto reached = scan_row(csv, 0.7, 4e-6);
  CHECK(reached.at("verdict") == "unstable");
  CHECK(reached.at("spectrum_converged") == "yes");
  CHECK_THAT(reached.at("steady_how"), Contains("has no positive root below lambda = 7.4") &&
                                           Contains("on the refined grid graded(K=16; r=1.05; three-moment): continuation from lambda = 0.1"));
  const auto none = scan_row(csv, 0.7, 1e-9);
  CHECK(none.at("verdict") == "no-positive-steady-state");
  CHECK_THAT(none.at("steady_how"), Contains("stopped at lambda = 2.7"));
  // Both pictures, also where a row has no steady state to draw (the bifurcation diagram's log scale).
  CHECK(aggkit::testing::read_text(folder / "out" / "phase_diagram.png").substr(1, 3) == "PNG");
  CHECK(aggkit::testing::read_text(folder / "out" / "bifurcation.png").substr(1, 3) == "PNG");
}

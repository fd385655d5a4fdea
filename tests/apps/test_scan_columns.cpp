// The attracting cycle continued down the columns of `aggkit scan` (cycle_column): the points it decides, the
// order of the walk, where and why a column stops, its absolute tolerances far below the curve, and the column
// files of earlier versions read back.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "tests/apps/scan_cli_fixture.hpp"

using Catch::Matchers::Contains;
using namespace aggkit::testing::scan;

namespace {

// a = 0.9 on the coarse grid (λ_crit 0.0027 there) at λ = 1e-4, 3.2e-4 and 0.001: with cycle_run = 100 no
// point's own search can reach its cycle below 0.001.
std::string column_scan() {
  std::string text = coarse_scan;
  text.replace(text.find("a = [0.85, 0.9]"), 15, "a = [0.9]");
  text.replace(text.find("lambda = [0.001, 0.004, 0.012]"), 30, "lambda = [0.0001, 0.000316227766, 0.001]");
  return text + "refine = false\ncycle_run = 100\n";
}

// Steps cached by earlier versions of the column files, in the folder of the test below, read back.
void check_earlier_column_files(const fs::path& folder, const fs::path& with, const fs::path& csv, const std::string& first) {
  // Steps cached by earlier versions read back: one without what it saw of the grid's end (the last two
  // columns), one also without its step budget (the last three), one also without atol and atol_mass (the last
  // five; its run took the integrator's default atol, rtol/100, and no bound) and one also without its settling
  // (the last eight; read back as settled where converged). Still nothing to compute, and the same scan.csv but
  // for the tolerances the notes name.
  const auto step = folder / "out" / "points" / "cycle_column_a0.9_lambda1e-04_N1048576.csv";
  const std::string current = aggkit::testing::read_text(step);
  const auto without_fields = [&](int fields) {
    std::istringstream lines(current);
    std::string older;
    for (std::string line; std::getline(lines, line);) {
      for (int field = 0; field < fields; ++field) line.erase(line.rfind(','));
      older += line + "\n";
    }
    return older;
  };
  const std::string adopted_now = scan_row(csv, 0.9, 0.0001).at("note");
  REQUIRE_THAT(adopted_now, Contains("atol_k = 1e-16 / k^3 at least 1e-16 and at most 1e-15 M / x_k"));
  // On this grid (N = 2^20) the step at 1e-4 lost 1.3e-4 of the mass through N, which its point's note says where
  // the step's file records it; a file from before reads as unknown there.
  std::string plain = first;
  const std::string said = "; the cycle reaches the grid's end", said_end = "its figures depend on N";
  const std::size_t said_at = plain.find(said);
  REQUIRE(said_at != std::string::npos);
  plain.erase(said_at, plain.find(said_end, said_at) + said_end.size() - said_at);
  for (const int fields : {2, 3, 5, 8}) {
    const std::string older = without_fields(fields);
    REQUIRE(older.find("top_octave_mass") == std::string::npos);
    REQUIRE((older.find("step_budget") == std::string::npos) == (fields >= 3));
    REQUIRE((older.find("atol_mass") == std::string::npos) == (fields >= 5));
    REQUIRE((older.find("settl") == std::string::npos) == (fields == 8));
    aggkit::testing::write_text(step, older);
    const Outcome before = run(scan_command("", with, folder / "out"), folder);
    INFO(fields << " fields fewer: " << before.err);
    REQUIRE(before.exit_code == 0);
    CHECK_THAT(before.err, Contains("continued down 1 columns of lambda, and the converged Hopf curve: 2 runs, 2 finished earlier, 0 to compute"));
    const auto row = scan_row(csv, 0.9, 0.0001);
    CHECK(row.at("verdict") == "sustained");
    if (fields <= 3) {  // its tolerances are on record; what its run saw of the grid's end is not
      CHECK(aggkit::testing::read_text(csv) == plain);
      continue;
    }
    CHECK_THAT(row.at("note"), Contains("atol_k = 1e-08 / k^3 at least 1e-16)"));
    // Only that point's row differs, and only in the tolerances its note names.
    const auto lines = [](const std::string& text) {
      std::vector<std::string> all;
      std::istringstream in(text);
      for (std::string line; std::getline(in, line);) all.push_back(line);
      return all;
    };
    const std::vector<std::string> was = lines(plain), is = lines(aggkit::testing::read_text(csv));
    REQUIRE(was.size() == is.size());
    std::size_t differing = 0;
    for (std::size_t i = 0; i < was.size(); ++i) {
      if (was[i] == is[i]) continue;
      ++differing;
      std::string expected = was[i];
      const std::size_t at = expected.find("atol_k = 1e-16 / k^3 at least 1e-16 and at most 1e-15 M / x_k");
      REQUIRE(at != std::string::npos);
      CHECK(expected.replace(at, 62, "atol_k = 1e-08 / k^3 at least 1e-16)") == is[i]);
    }
    CHECK(differing == 1);
  }
}

// The column's step at (0.9, 0.001) against the cycle shot there from the point's own search.
void check_against_the_shot_cycle(const fs::path& folder) {
  // Against the cycle shot at (0.9, 0.001) from the point's own search (no cycle_run limit; Newton-Krylov on the
  // period map at rtol 1e-10): the column's period there, from the turning points of a run's last 6 periods
  // sampled 50 times a period at rtol 1e-6, agrees to 1e-3 (measured: 2e-5).
  std::string shot = coarse_scan;
  shot.replace(shot.find("a = [0.85, 0.9]"), 15, "a = [0.9]");
  shot.replace(shot.find("lambda = [0.001, 0.004, 0.012]"), 30, "lambda = [0.001]");
  const Outcome shooting = run(scan_command("", aggkit::testing::write_text(folder / "shot.toml", shot + "refine = false\n"),
                                            folder / "shot"), folder);
  REQUIRE(shooting.exit_code == 0);
  const double shot_period = std::stod(scan_row(folder / "shot" / "scan.csv", 0.9, 0.001).at("cycle_period"));
  const auto column_cycle = aggkit::testing::read_csv(folder / "out" / "points" / "cycle_column_a0.9_lambda0.001_N1048576.csv");
  REQUIRE(column_cycle.size() == 1);
  CHECK(std::stod(column_cycle.front().at("period")) == Approx(shot_period).epsilon(1e-3));
  // The column's multiplier there, from the return map of the step's run, against Arnoldi's on the shot cycle
  // (solvers/limit_cycle.hpp at rtol 1e-10), an independent method. The return map's floor is 3 times the step's
  // own period spread, which is the run's noise at rtol 1e-6 and moves with round-off: at a spread of 2.2e-5 the
  // third return lay above it and the fit over the second and third read 0.218 against 0.220; at 4.2e-5 (the same
  // run with the rates summed in another order) it fell within it and the second return bounds |μ_1| by 0.358.
  // Either is checked against Arnoldi's: a fit to 20 %, a bound not below it.
  const auto multiplier = aggkit::testing::read_csv(folder / "out" / "points" / "cycle_column_a0.9_lambda0.001_N1048576_floquet.csv");
  REQUIRE(multiplier.size() == 1);
  const double arnoldi = std::stod(scan_row(folder / "shot" / "scan.csv", 0.9, 0.001).at("floquet_max"));
  INFO("return map " << multiplier.front().at("multiplier") << " (" << multiplier.front().at("note") << "), Arnoldi " << arnoldi);
  if (multiplier.front().at("bounded") == "yes") {
    CHECK(std::stod(multiplier.front().at("multiplier")) >= arnoldi);
    CHECK(std::stod(multiplier.front().at("multiplier")) < 1.0);
  } else {
    CHECK(std::stod(multiplier.front().at("multiplier")) == Approx(arnoldi).epsilon(0.2));
  }
  // Next to the curve the first level of absolute tolerances settles.
  CHECK(column_cycle.front().at("atol") == "1e-16");
  CHECK(column_cycle.front().at("atol_floor") == "1e-16");
  CHECK(column_cycle.front().at("atol_mass") == "1e-15");
  // Its mass changed by less than the guard's 1e-3 (measured: -1.8e-5, the drop truncation's loss).
  CHECK(std::abs(std::stod(column_cycle.front().at("mass_change"))) < 1e-3);
  // Its periods settled on one cycle (no modulation: spread within 2e-3).
  CHECK(column_cycle.front().at("settling") == "settled");
  CHECK(std::stod(column_cycle.front().at("spread")) <= 2e-3);

}

}  // namespace

TEST_CASE("scan cli: the cycle continued down a column decides the points whose own search cannot reach it") {
  // The points below 0.001 stay "unstable" without the column. The column starts on the Hopf normal form's
  // cycle at 0.95 λ_crit and steps down to λ = 0.001, 3.2e-4 and 1e-4, each a run of 12 predicted periods from
  // the cycle above.
  const auto folder = aggkit::testing::scratch_folder("scan-cli-column");
  const std::string text = column_scan();
  const auto without = aggkit::testing::write_text(folder / "without.toml", text);
  const auto with = aggkit::testing::write_text(folder / "with.toml", text + "cycle_column = 12\n");
  const Outcome plain = run(scan_command("", without, folder / "out"), folder);
  INFO(plain.err);
  REQUIRE(plain.exit_code == 0);
  const fs::path csv = folder / "out" / "scan.csv";
  // (0.9, 0.001) is sustained by its own run over [time]; below it the runs end before the cycle shows.
  CHECK(scan_row(csv, 0.9, 0.001).at("verdict") == "sustained");
  for (const double lambda : {0.000316227766, 0.0001}) {
    const auto row = scan_row(csv, 0.9, lambda);
    INFO(lambda << ": " << row.at("note"));
    CHECK(row.at("verdict") == "unstable");
  }

  // cycle_column is not part of the fingerprint: the points are reused, only the column is computed.
  const Outcome column = run(scan_command("", with, folder / "out"), folder);
  INFO(column.err);
  REQUIRE(column.exit_code == 0);
  CHECK_THAT(column.err, Contains("3 runs, 3 finished earlier, 0 to compute") &&
                             Contains("continued down 1 columns of lambda, and the converged Hopf curve: 2 runs, 1 finished earlier, 1 to compute"));
  double above = std::stod(scan_row(csv, 0.9, 0.001).at("period"));
  for (const double lambda : {0.000316227766, 0.0001}) {
    const auto row = scan_row(csv, 0.9, lambda);
    INFO(lambda << ": " << row.at("note"));
    CHECK(row.at("verdict") == "sustained");
    CHECK(row.at("regime") == "sustained");
    CHECK(row.at("agree") == "yes");
    CHECK_THAT(row.at("note"), Contains("continued down the column: the run is 12 predicted periods from the cycle at lambda = "));
    const double period = std::stod(row.at("period"));
    CHECK(period > 1.5 * above);  // the periods grow down the column (about as 1/lambda)
    above = period;
    // Each an attracting cycle by its largest nontrivial Floquet multiplier, from the return map.
    CHECK_THAT(row.at("note"), Contains("largest nontrivial Floquet multiplier from the return map"));
    CHECK(std::stod(row.at("floquet_max")) > 0.0);
    CHECK(std::stod(row.at("floquet_max")) < 1.0);
    CHECK(row.at("cycle_stable") == "yes");
  }
  CHECK(fs::exists(folder / "out" / "points" / "cycle_column_a0.9_lambda1e-04_N1048576_state.txt"));

  check_against_the_shot_cycle(folder);

  // Resumed: nothing is computed again and scan.csv is the same, byte for byte.
  const std::string first = aggkit::testing::read_text(csv);
  const Outcome again = run(scan_command("", with, folder / "out"), folder);
  REQUIRE(again.exit_code == 0);
  CHECK_THAT(again.err, Contains("continued down 1 columns of lambda, and the converged Hopf curve: 2 runs, 2 finished earlier, 0 to compute"));
  CHECK(aggkit::testing::read_text(csv) == first);

  check_earlier_column_files(folder, with, csv, first);
}

TEST_CASE("scan cli: the columns are walked first, and a point its column reached seeks no cycle of its own") {
  // A fresh scan with cycle_column: the criticality and the column come before the points, and the points the
  // column reached (0.001 and below, all under 0.95 lambda_crit = 0.00252 on this grid) neither search nor shoot
  // a cycle of their own; those below 0.001, whose runs over [time] do not show the cycle, take the column's.
  const auto folder = aggkit::testing::scratch_folder("scan-cli-column-first");
  const auto with = aggkit::testing::write_text(folder / "with.toml", column_scan() + "cycle_column = 12\n");
  const Outcome first = run(scan_command("", with, folder / "out"), folder);
  INFO(first.err);
  REQUIRE(first.exit_code == 0);
  const std::size_t column = first.err.find("continued down 1 columns of lambda, and the converged Hopf curve: 2 runs, 0 finished earlier, 2 to compute");
  const std::size_t points = first.err.find("grid of 1 a x 3 lambda");
  REQUIRE(column != std::string::npos);
  REQUIRE(points != std::string::npos);
  CHECK(points > column);
  const fs::path csv = folder / "out" / "scan.csv";
  for (const double lambda : {0.001, 0.000316227766, 0.0001}) {
    const auto row = scan_row(csv, 0.9, lambda);
    INFO(lambda << ": " << row.at("note"));
    CHECK(row.at("verdict") == "sustained");
    CHECK_THAT(row.at("note"), Contains("no cycle search of its own: the cycle continued down the column reached this point (period "));
    CHECK(row.at("cycle_period") == "nan");  // nothing shot
    // The column's settled cycle at this λ gives the point its largest Floquet multiplier, also where the point's
    // own confirmation run (0.001) decided it sustained.
    CHECK(row.at("cycle_stable") == "yes");
    CHECK(std::stod(row.at("floquet_max")) < 1.0);
  }
  CHECK_THAT(scan_row(csv, 0.9, 0.001).at("note"), Contains("the column's cycle: largest nontrivial Floquet multiplier from the return map"));
  for (const auto& [lambda, name] : {std::pair{0.000316227766, "0.000316227766"}, std::pair{0.0001, "1e-04"}}) {
    const auto row = scan_row(csv, 0.9, lambda);
    const auto step = aggkit::testing::read_csv(folder / "out" / "points" /
                                                (std::string("cycle_column_a0.9_lambda") + name + "_N1048576.csv"));
    REQUIRE(step.size() == 1);
    CHECK(row.at("period") == step.front().at("period"));
    CHECK_THAT(row.at("note"), Contains("sustained on the cycle continued down the column"));
  }
}

TEST_CASE("scan cli: a column that stops decides nothing and the points below say where and why") {
  // Here at once: the first run needs more than column_steps (by default cycle_steps = 100) at every level of
  // absolute tolerances.
  const auto folder = aggkit::testing::scratch_folder("scan-cli-column-stopped");
  const auto stopped = aggkit::testing::write_text(folder / "stopped.toml", column_scan() + "cycle_column = 12\ncycle_steps = 100\n");
  const Outcome stop = run(scan_command("", stopped, folder / "stopped"), folder);
  INFO(stop.err);
  REQUIRE(stop.exit_code == 0);
  for (const double lambda : {0.000316227766, 0.0001}) {
    const auto row = scan_row(folder / "stopped" / "scan.csv", 0.9, lambda);
    CHECK(row.at("verdict") == "unstable");
    CHECK_THAT(row.at("note"), Contains("no cycle from the column either: at lambda = 0.00251999") &&
                                   Contains("needs more than column_steps = 100 steps"));
    // The first level ran out of steps, so the finer one (which takes more steps still) was not run.
    CHECK_THAT(row.at("note"), Contains("atol 1e-16 with floor 1e-16 and atol_mass 1e-15: ") &&
                                   Contains("; the finer floors not run: they take more steps still"));
    CHECK_THAT(row.at("note"), !Contains("atol_mass 1e-18: "));
  }
  // The stopped step's record is the last level run: the step at 0.95 λ_crit, whose file name carries λ to
  // every digit (those past the 12th move with the rates' round-off).
  fs::path stopped_step;
  for (const auto& entry : fs::directory_iterator(folder / "stopped" / "points"))
    if (const std::string name = entry.path().filename().string();
        name.starts_with("cycle_column_a0.9_lambda0.00251999891") && name.ends_with("_N1048576.csv"))
      stopped_step = entry.path();
  REQUIRE_FALSE(stopped_step.empty());
  const auto record = aggkit::testing::read_csv(stopped_step);
  REQUIRE(record.size() == 1);
  CHECK(record.front().at("atol_floor") == "1e-16");
  CHECK(record.front().at("atol_mass") == "1e-15");
  CHECK(record.front().at("step_budget") == "100");
  CHECK(record.front().at("regime").empty());

  // A larger budget for the columns alone (column_steps is not part of the points' fingerprint): the points are
  // reused, the step the budget stopped is run again, and the column reaches the points below.
  const auto larger = aggkit::testing::write_text(folder / "larger.toml", column_scan() + "cycle_column = 12\ncycle_steps = 100\ncolumn_steps = 40000\n");
  const Outcome again = run(scan_command("", larger, folder / "stopped"), folder);
  INFO(again.err);
  REQUIRE(again.exit_code == 0);
  CHECK_THAT(again.err, Contains("3 runs, 3 finished earlier, 0 to compute") &&
                            Contains("continued down 1 columns of lambda, and the converged Hopf curve: 2 runs, 1 finished earlier, 1 to compute"));
  for (const double lambda : {0.000316227766, 0.0001})
    CHECK(scan_row(folder / "stopped" / "scan.csv", 0.9, lambda).at("verdict") == "sustained");
  // A settled step walked under the larger budget keeps it for its return map: rerun under column_steps = 100 with
  // the multipliers' files gone, the steps are reused and the return maps (which need more than 100 steps) run again.
  std::vector<fs::path> multipliers;
  for (const auto& entry : fs::directory_iterator(folder / "stopped" / "points"))
    if (entry.path().filename().string().ends_with("_floquet.csv")) multipliers.push_back(entry.path());
  REQUIRE(multipliers.size() == 3);  // at 0.001, 3.16e-4 and 1e-4
  for (const auto& file : multipliers) fs::remove(file);
  const auto smaller = aggkit::testing::write_text(folder / "smaller.toml", column_scan() + "cycle_column = 12\ncycle_steps = 100\ncolumn_steps = 100\n");
  const Outcome remeasured = run(scan_command("", smaller, folder / "stopped"), folder);
  INFO(remeasured.err);
  REQUIRE(remeasured.exit_code == 0);
  for (const auto& file : multipliers) {
    const auto multiplier = aggkit::testing::read_csv(file);
    REQUIRE(multiplier.size() == 1);
    INFO(file << ": " << multiplier.front().at("note"));
    CHECK(multiplier.front().at("note").find("max_steps") == std::string::npos);
  }
  // Without cycle_column there are no columns to budget.
  const auto orphan = aggkit::testing::write_text(folder / "orphan.toml", column_scan() + "column_steps = 40000\n");
  const Outcome refused = run(scan_command("", orphan, folder / "orphan"), folder);
  CHECK(refused.exit_code == 2);
  CHECK_THAT(refused.err, Contains("column_steps"));
}

TEST_CASE("scan cli: far below the curve the column resolves the quiescent phase of the relaxation cycles") {
  // a = 0.75 on a coarse graded grid up to N = 2^40 (λ_crit = 2.6e-4 on it): the column walks from 0.95 λ_crit
  // down to λ = 1e-8, 10 steps of 12 predicted periods at most 10^(1/2) apart. There the quiescent phase between
  // bursts holds M0 ~ 1e-5 and the monomers far below 1e-8, the integrator's default atol for n_1: with it (and
  // the floors 1e-8 … 1e-12 tried before) the column stopped at λ = 1.78e-7 ("does not oscillate"; the run at
  // the finest floor failed), and with atol 1e-16 but no atol_mass it fails too. With the monomers' atol 1e-16
  // and no class's tolerance worth more than 1e-15 of the mass it reaches 1e-8, every step settled with its
  // mass kept.
  const auto folder = aggkit::testing::scratch_folder("scan-cli-column-far");
  std::string text = coarse_scan;  // its grid, up to N = 2^40
  text.replace(text.find("a = 0.9 }"), 9, "a = 0.75 }");
  text.replace(text.find("size = 1048576"), 14, "size = 1099511627776");
  text.replace(text.find("a = [0.85, 0.9]"), 15, "a = [0.75]");
  text.replace(text.find("lambda = [0.001, 0.004, 0.012]"), 30, "lambda = [1e-8, 1e-6]");
  const auto scene = aggkit::testing::write_text(folder / "far.toml", text + "refine = false\ncycle_run = 100\ncycle_column = 12\n");
  const Outcome outcome = run(scan_command("", scene, folder / "out"), folder);
  INFO(outcome.err);
  REQUIRE(outcome.exit_code == 0);
  std::map<double, double> period;
  for (const auto& [lambda, name] : {std::pair{1e-8, "1e-08"}, std::pair{1e-6, "1e-06"}}) {
    const auto row = scan_row(folder / "out" / "scan.csv", 0.75, lambda);
    INFO(lambda << ": " << row.at("note"));
    CHECK(row.at("verdict") == "sustained");
    CHECK_THAT(row.at("note"), Contains("continued down the column"));
    const auto step = aggkit::testing::read_csv(folder / "out" / "points" /
                                                (std::string("cycle_column_a0.75_lambda") + name + "_N1099511627776.csv"));
    REQUIRE(step.size() == 1);
    CHECK(step.front().at("settling") == "settled");
    CHECK(std::abs(std::stod(step.front().at("mass_change"))) < 1e-3);
    CHECK(std::stod(step.front().at("m0_min")) > 0.0);
    period[lambda] = std::stod(step.front().at("period"));
  }
  // Relaxation cycles: the period grows about as 1/λ (measured: 1.407e7 and 1.535e5, a ratio of 91.7).
  CHECK(period[1e-8] / period[1e-6] == Approx(100).epsilon(0.2));
}

TEST_CASE("scan cli: a cycle that outgrows the grid makes the points at and below its column's stop not representable") {
  // a = 1 on the coarse grid, cut at N = 2^14 and at 2^17. Down the column the quiescent phase grows larger
  // clusters (the period ~1/λ). At N = 2^14 the step at λ = 2.2e-3 lost 4 % of the mass through N and its periods
  // drift (spread 5e-3), so the unstable point at λ = 0.001 below it cannot be decided on this grid; at N = 2^17 the
  // column settles at 0.001 (a leak of 1.3e-5, period 120.85) and outgrows the grid further down, at 3.2e-4
  // (4 % lost again), so the point at 1e-4 is the one it cannot decide.
  const auto folder = aggkit::testing::scratch_folder("scan-cli-column-outgrown");
  const auto scene = [&](const std::string& size) {
    std::string text = coarse_scan;
    text.replace(text.find("a = 0.9 }"), 9, "a = 1.0 }");
    text.replace(text.find("size = 1048576"), 14, "size = " + size);
    text.replace(text.find("a = [0.85, 0.9]"), 15, "a = [1.0]");
    text.replace(text.find("lambda = [0.001, 0.004, 0.012]"), 30, "lambda = [0.0001, 0.001]");
    return aggkit::testing::write_text(folder / ("N" + size + ".toml"), text + "refine = false\ncycle_run = 100\ncycle_column = 12\n");
  };
  const Outcome shorter = run(scan_command("", scene("16384"), folder / "short"), folder);
  INFO(shorter.err);
  REQUIRE(shorter.exit_code == 0);
  const auto undecided = scan_row(folder / "short" / "scan.csv", 1.0, 0.001);
  INFO(undecided.at("note"));
  CHECK(undecided.at("verdict") == "not-representable");
  CHECK_THAT(undecided.at("note"), Contains("outgrows N at lambda = 0.00219") && Contains("N = 16384") &&
                                       Contains("the cycles below it are longer still"));
  // The step that stopped the column keeps what its run saw of the grid's end.
  bool found = false;
  for (const auto& entry : fs::directory_iterator(folder / "short" / "points"))
    if (const std::string name = entry.path().filename().string();
        name.starts_with("cycle_column_a1_lambda0.00219") && name.ends_with("_N16384.csv")) {
      const auto step = aggkit::testing::read_csv(entry.path());
      REQUIRE(step.size() == 1);
      CHECK(std::stod(step.front().at("leaked_mass")) > 1e-2);
      CHECK(step.front().at("regime") == "sustained");  // oscillating, but not on one cycle
      found = true;
    }
  CHECK(found);
  // A stop for the grid's end is kept under another step budget (a budget's stop would be run again).
  const auto budget = aggkit::testing::write_text(
      folder / "budget.toml", aggkit::testing::read_text(scene("16384")) + "column_steps = 80000\n");
  const Outcome again = run(scan_command("", budget, folder / "short"), folder);
  INFO(again.err);
  REQUIRE(again.exit_code == 0);
  CHECK_THAT(again.err, Contains("continued down 1 columns of lambda, and the converged Hopf curve: 2 runs, 2 finished earlier, 0 to compute"));
  CHECK(scan_row(folder / "short" / "scan.csv", 1.0, 0.001).at("verdict") == "not-representable");
  // Eight times the grid: the same point is sustained, and the verdict moves down to the point below.
  const Outcome longer = run(scan_command("", scene("131072"), folder / "long"), folder);
  INFO(longer.err);
  REQUIRE(longer.exit_code == 0);
  CHECK(scan_row(folder / "long" / "scan.csv", 1.0, 0.001).at("verdict") == "sustained");
  const auto below = scan_row(folder / "long" / "scan.csv", 1.0, 0.0001);
  CHECK(below.at("verdict") == "not-representable");
  CHECK_THAT(below.at("note"), Contains("outgrows N at lambda = 0.000316") && Contains("N = 131072"));
}

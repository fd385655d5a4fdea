// `aggkit sweep` end to end: the rows of the product of the keys with their final values (checked against the
// constant kernel's exact M0 = 2/(2 + t)), the same sweep.csv from one process and from `mpirun -np 2`, means
// and standard errors of realizations against a direct computation from sweep.csv, resumption without rerunning
// finished runs, heat maps, and bad keys (exit 2, no outputs).
#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <sstream>
#include <sys/wait.h>

#include "tests/apps/command_fixture.hpp"
#include "tests/validation/scene_fixture.hpp"

using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {


using aggkit::testing::quoted;

std::string sweep_command(const std::string& prefix, const fs::path& scene, const fs::path& out, bool plot = false) {
  std::string command = prefix + quoted(AGGKIT_CLI) + " sweep " + quoted(scene.string()) + " --out " + quoted(out.string());
  if (!plot) command += " --no-plot";
  return command;
}

using Outcome = aggkit::testing::CommandOutcome;
using aggkit::testing::mpirun;

Outcome run(const std::string& command, const fs::path& folder) { return aggkit::testing::run_command(command, folder); }

using Table = aggkit::testing::CsvTable;
using aggkit::testing::read_csv;

// CVODE on the constant kernel, pure aggregation (M0 = 2/(2 + t) exactly [Leyvraz2003]), N = 256 (tail weight
// (t/(t+2))^256 < 1e-40 at t <= 4): 3 end times x 2 tolerances, each run a few milliseconds.
const char* const kinetic_sweep = R"(
name = "kinetic-sweep"
[model]
kernel = { name = "constant" }
lambda = 0.0
size = 256
[time]
end = 1.0
[[engine]]
name = "cvode"
rtol = 1e-8
atol = 1e-14
[observe]
series = ["M0", "M2"]
[sweep]
"time.end" = [1.0, 2.0, 4.0]
"engine.rtol" = { from = 1e-10, to = 1e-8, count = 2, spacing = "log" }
)";

// 30 DEM spheres with random velocities in a periodic box: three realizations per point differ.
const char* const dem_sweep = R"(
name = "dem-sweep"
[particles]
dimension = 3
count = 30
radius = 1.0
mass = 1.0
boundary = "periodic"
volume_fraction = 0.1
initial = { cloud = "cube", speed = 1.0 }
seed = 3
[time]
end = 0.5
[[engine]]
name = "dem"
restitution = 0.5
contact_time = 0.05
[observe]
series = ["kinetic_energy"]
final = ["kinetic_energy", "clusters"]
[sweep]
"engine.restitution" = [0.3, 0.9]
realizations = 3
)";

std::map<std::string, std::string> point_files(const fs::path& out) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::directory_iterator(out / "points"))
    if (entry.path().extension() == ".json") files[entry.path().filename().string()] = aggkit::testing::read_text(entry.path());
  return files;
}

}  // namespace

TEST_CASE("sweep cli: the product of the keys, one row per run with its final values, and the same CSV under mpirun -np 2", "[mpi]") {
  const auto folder = aggkit::testing::scratch_folder("sweep-cli-kinetic");
  const auto scene = aggkit::testing::write_text(folder / "sweep.toml", kinetic_sweep);
  const Outcome single = run(sweep_command("", scene, folder / "single"), folder);
  INFO(single.err);
  REQUIRE(single.exit_code == 0);
  CHECK_THAT(single.err, Contains("6 runs, 0 finished earlier, 6 to compute on 1 rank"));
  CHECK(aggkit::testing::first_line(folder / "single" / "sweep.csv") == "time.end,engine.rtol,realization,M0,M2");
  const Table rows = read_csv(folder / "single" / "sweep.csv");
  REQUIRE(rows.size() == 6);
  const double ends[] = {1, 1, 2, 2, 4, 4};
  const double rtols[] = {1e-10, 1e-8, 1e-10, 1e-8, 1e-10, 1e-8};
  for (std::size_t i = 0; i < 6; ++i) {
    CHECK(std::stod(rows[i].at("time.end")) == ends[i]);
    CHECK(std::stod(rows[i].at("engine.rtol")) == Approx(rtols[i]).epsilon(1e-12));
    CHECK(rows[i].at("realization") == "0");
    // Each run ran its own end time: M0(T) = 2/(2 + T), M2 = 1 + T, to CVODE's tolerance (rtol 1e-8: 1e-6 is
    // a factor 100 above the errors these tolerances give on this problem).
    CHECK(std::stod(rows[i].at("M0")) == Approx(2 / (2 + ends[i])).epsilon(1e-6));
    CHECK(std::stod(rows[i].at("M2")) == Approx(1 + ends[i]).epsilon(1e-6));
  }
  const Table means = read_csv(folder / "single" / "sweep_mean.csv");
  REQUIRE(means.size() == 6);
  CHECK(means[0].at("runs") == "1");
  CHECK(means[0].at("M0_stderr") == "0");
  CHECK(fs::exists(folder / "single" / "runs" / "point5_r0" / "cvode" / "series.csv"));

  const Outcome two = run(sweep_command(mpirun(2), scene, folder / "two"), folder);
  INFO(two.err);
  REQUIRE(two.exit_code == 0);
  CHECK(aggkit::testing::read_text(folder / "single" / "sweep.csv") == aggkit::testing::read_text(folder / "two" / "sweep.csv"));
  CHECK_THAT(aggkit::testing::read_text(folder / "two" / "timing.csv"), Contains(",0\n") && Contains(",1\n"));
  CHECK_THAT(two.err, Contains("[rank 1]"));
}

TEST_CASE("sweep cli: realizations differ, and sweep_mean.csv holds their means and standard errors") {
  const auto folder = aggkit::testing::scratch_folder("sweep-cli-dem");
  const auto scene = aggkit::testing::write_text(folder / "sweep.toml", dem_sweep);
  const Outcome outcome = run(sweep_command("", scene, folder / "out"), folder);
  INFO(outcome.err);
  REQUIRE(outcome.exit_code == 0);
  const Table rows = read_csv(folder / "out" / "sweep.csv");
  REQUIRE(rows.size() == 6);
  const Table means = read_csv(folder / "out" / "sweep_mean.csv");
  REQUIRE(means.size() == 2);
  for (std::size_t p = 0; p < 2; ++p) {
    // Direct: the mean and standard error (sample sd / √3) of the three rows of the point.
    double sum = 0, squares = 0;
    std::vector<double> k;
    for (std::size_t r = 0; r < 3; ++r) {
      CHECK(rows[3 * p + r].at("realization") == std::to_string(r));
      CHECK(rows[3 * p + r].at("engine.restitution") == means[p].at("engine.restitution"));
      k.push_back(std::stod(rows[3 * p + r].at("kinetic_energy")));
      sum += k.back();
    }
    const double mean = sum / 3;
    for (double v : k) squares += (v - mean) * (v - mean);
    CHECK(k[0] != k[1]);  // different seeds
    CHECK(means[p].at("runs") == "3");
    CHECK(means[p].at("kinetic_energy_n") == "3");
    // shortest_text round-trips: only the summation order can differ (a few ulps).
    CHECK(std::stod(means[p].at("kinetic_energy")) == Approx(mean).epsilon(1e-14));
    CHECK(std::stod(means[p].at("kinetic_energy_stderr")) == Approx(std::sqrt(squares / 2 / 3)).epsilon(1e-12));
  }
  // Realization 1 of point 0 is the scene run with seed 3 + 1 (and restitution 0.3) by `aggkit run`.
  std::string single = dem_sweep;
  single = single.substr(0, single.find("[sweep]"));
  single.replace(single.find("seed = 3"), 8, "seed = 4");
  single.replace(single.find("restitution = 0.5"), 17, "restitution = 0.3");
  const auto single_scene = aggkit::testing::write_text(folder / "single.toml", single);
  REQUIRE(run(quoted(AGGKIT_CLI) + " run " + quoted(single_scene.string()) + " --out " + quoted((folder / "single").string()) +
                  " --no-plot",
              folder)
              .exit_code == 0);
  const std::string final_json = aggkit::testing::read_text(folder / "single" / "dem" / "final.json");
  const std::size_t at = final_json.find("\"kinetic_energy\":");
  REQUIRE(at != std::string::npos);
  CHECK(std::stod(final_json.substr(at + 17)) == Approx(std::stod(rows[1].at("kinetic_energy"))).epsilon(1e-12));
}

TEST_CASE("sweep cli: an interrupted sweep resumes without rerunning its finished runs, heat maps") {
  const auto folder = aggkit::testing::scratch_folder("sweep-cli-resume");
  const auto scene = aggkit::testing::write_text(folder / "sweep.toml", kinetic_sweep);
  const auto out = folder / "out";
  REQUIRE(run(sweep_command("", scene, out), folder).exit_code == 0);
  const std::string complete = aggkit::testing::read_text(out / "sweep.csv");
  const auto before = point_files(out);
  REQUIRE(before.size() == 6);
  // Killed: two runs lost, sweep.csv not yet written, a half-written record and a half-written run folder left.
  const std::string lost1 = before.begin()->first, lost2 = std::next(before.begin(), 3)->first;
  fs::remove(out / "points" / lost1);
  fs::remove(out / "points" / lost2);
  fs::remove(out / "sweep.csv");
  aggkit::testing::write_text(out / "points" / (lost1 + ".partial"), "{\"point\": 0, ");
  fs::remove(out / "runs" / lost1.substr(0, lost1.size() - 5) / "summary.json");
  const Outcome resumed = run(sweep_command("", scene, out, /*plot=*/true), folder);
  INFO(resumed.err);
  REQUIRE(resumed.exit_code == 0);
  CHECK_THAT(resumed.err, Contains("6 runs, 4 finished earlier, 2 to compute"));
  const auto after = point_files(out);
  REQUIRE(after.size() == 6);
  // Finished runs were not rerun: their records (with their wall time and rank) are unchanged.
  for (const auto& [name, text] : before)
    if (name != lost1 && name != lost2) CHECK(after.at(name) == text);
  CHECK(aggkit::testing::read_text(out / "sweep.csv") == complete);
  // Heat maps over the two keys (the series, without observe.final); where matplotlib is missing the sweep
  // says why and still succeeds.
  if (resumed.err.find("not drawn") == std::string::npos) {
    CHECK(aggkit::testing::read_text(out / "map_M0.png").substr(1, 3) == "PNG");
    CHECK(aggkit::testing::read_text(out / "map_M2.png").substr(1, 3) == "PNG");
  }
  // A changed scene does not reuse the old runs.
  std::string changed = kinetic_sweep;
  changed.replace(changed.find("size = 256"), 10, "size = 300");
  const Outcome rerun = run(sweep_command("", aggkit::testing::write_text(folder / "changed.toml", changed), out), folder);
  REQUIRE(rerun.exit_code == 0);
  CHECK_THAT(rerun.err, Contains("earlier results discarded") && Contains("0 finished earlier, 6 to compute"));
}

TEST_CASE("sweep cli: a key that is not a scene key is exit 2 naming it, with no outputs") {
  const auto folder = aggkit::testing::scratch_folder("sweep-cli-bad");
  for (const auto& [key, value] : std::vector<std::pair<std::string, std::string>>{
           {"engine.rtoll", "[1e-6]"}, {"model.sise", "[10]"}, {"particles.count", "[10]"}, {"model.size", "[64, 0]"}}) {
    std::string text = kinetic_sweep;
    text.replace(text.find("\"engine.rtol\""), std::string::npos, "\"" + key + "\" = " + value + "\n");
    const auto scene = aggkit::testing::write_text(folder / "bad.toml", text);
    const Outcome outcome = run(sweep_command("", scene, folder / "out"), folder);
    INFO(outcome.err);
    CHECK(outcome.exit_code == 2);
    CHECK_THAT(outcome.err, Contains("sweep.\"" + key + "\""));
    CHECK_FALSE(fs::exists(folder / "out"));
  }
  // A run scene without [sweep].
  const auto plain = aggkit::testing::write_text(folder / "plain.toml", std::string(kinetic_sweep).substr(0, std::string(kinetic_sweep).find("[sweep]")));
  const Outcome outcome = run(sweep_command("", plain, folder / "out"), folder);
  CHECK(outcome.exit_code == 2);
  CHECK_THAT(outcome.err, Contains("sweep"));
}

namespace {

// 100 cold self-gravitating DEM spheres (t_ff ≈ 6): at time.end = 2 no run has aggregated (T_agg undefined), at
// 12 every one has; two restitutions, two realizations each (and a third key of one value: the full map has a
// panel per value of it).
const char* const collapse_sweep = R"(
name = "collapse-sweep"
[particles]
dimension = 3
count = 100
radius = 1.0
mass = 1.0
boundary = "open"
initial = { cloud = "cube", volume_fraction = 0.05, speed = 0.0 }
seed = 5
[time]
end = 12.0
[[engine]]
name = "dem"
restitution = 0.1
contact_time = 0.05
gravity = { G = 1.0 }
[observe]
series = ["components_fraction"]
final = ["components_fraction", "fractal_dimension_com"]
[sweep]
"time.end" = [2.0, 12.0]
"engine.restitution" = [0.1, 0.3]
"engine.contact_time" = [0.05]
realizations = 2
group_by = ["engine.restitution", ["time.end"]]
where_not_aggregated = { fractal_dimension_com = 0.0 }
maps = ["fractal_dimension_com"]
)";

}  // namespace

TEST_CASE("sweep cli: means pooled over swept keys equal a direct computation over sweep.csv, F := 0 where T_agg is undefined") {
  const auto folder = aggkit::testing::scratch_folder("sweep-cli-pooled");
  const auto scene = aggkit::testing::write_text(folder / "sweep.toml", collapse_sweep);
  const Outcome outcome = run(sweep_command("", scene, folder / "out", true), folder);
  INFO(outcome.err);
  REQUIRE(outcome.exit_code == 0);
  const Table rows = read_csv(folder / "out" / "sweep.csv");
  REQUIRE(rows.size() == 8);
  for (const auto& row : rows) {
    const bool early = row.at("time.end") == "2";
    CHECK((row.at("aggregation_time") == "nan") == early);
    if (early) CHECK(row.at("fractal_dimension_com") == "0");  // set: the run never aggregated
    else CHECK(std::stod(row.at("fractal_dimension_com")) > 1);
  }
  // Each grouping's table against the direct mean and standard error of the rows sharing its values.
  for (const std::string key : {"engine.restitution", "time.end"}) {
    INFO(key);
    const Table pooled = read_csv(folder / "out" / ("sweep_mean_by_" + key + ".csv"));
    REQUIRE(pooled.size() == 2);
    for (const auto& group : pooled) {
      CHECK(group.at("runs") == "4");
      for (const std::string column : {"components_fraction", "fractal_dimension_com", "aggregation_time"}) {
        std::vector<double> values;
        for (const auto& row : rows)
          if (row.at(key) == group.at(key) && row.at(column) != "nan") values.push_back(std::stod(row.at(column)));
        CHECK(group.at(column + "_n") == std::to_string(values.size()));
        if (values.empty()) {
          CHECK(group.at(column) == "nan");
          continue;
        }
        double sum = 0, squares = 0;
        for (double v : values) sum += v;
        const double mean = sum / double(values.size());
        for (double v : values) squares += (v - mean) * (v - mean);
        CHECK(std::stod(group.at(column)) == Approx(mean).epsilon(1e-14).margin(1e-300));
        if (values.size() > 1)
          CHECK(std::stod(group.at(column + "_stderr")) ==
                Approx(std::sqrt(squares / double(values.size() - 1) / double(values.size()))).epsilon(1e-12).margin(1e-300));
      }
    }
  }
  CHECK(fs::exists(folder / "out" / "map_fractal_dimension_com.png"));
  CHECK(fs::exists(folder / "out" / "map_fractal_dimension_com_by_engine.restitution.png"));
  CHECK(fs::exists(folder / "out" / "map_fractal_dimension_com_by_time.end.png"));
}

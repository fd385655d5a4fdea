// The sweep plan ([sweep] of a scene): the product of the keys' values in the order written, each point's
// scene, the seeds of realizations, the engine-naming rules, bad keys named; and the CSV tables built from
// finished runs (means and standard errors against a direct computation).
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <limits>

#include "analysis/input_error.hpp"
#include "validation/sweep/sweep.hpp"
#include "validation/sweep/sweep_plan.hpp"
#include "validation/sweep/sweep_record.hpp"

using namespace aggkit;
using Catch::Matchers::Contains;

namespace {

// A CVODE scene (constant kernel, N = 64) with a [sweep] body.
std::string kinetic(const std::string& sweep, const std::string& engines = "[[engine]]\nname = \"cvode\"\nrtol = 1e-8\n") {
  return "name = \"sweep-test\"\n[model]\nkernel = { name = \"constant\" }\nlambda = 0.0\nsize = 64\n[time]\nend = 1.0\n" +
         engines + "[observe]\nseries = [\"M0\", \"M2\"]\n[sweep]\n" + sweep;
}

// 20 DEM spheres in a periodic box, no gravity.
std::string particles(const std::string& sweep) {
  return "name = \"sweep-dem\"\n[particles]\ndimension = 3\ncount = 20\nradius = 1.0\nmass = 1.0\nboundary = \"periodic\"\n"
         "initial = { cloud = \"cube\", speed = 1.0 }\nvolume_fraction = 0.1\nseed = 7\n[time]\nend = 0.2\n[[engine]]\n"
         "name = \"dem\"\nrestitution = 0.5\ncontact_time = 0.05\n[observe]\nseries = [\"kinetic_energy\"]\n"
         "final = [\"kinetic_energy\"]\n[sweep]\n" + sweep;
}

std::string error_of(const std::string& text) {
  try {
    parse_sweep_plan(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("sweep plan: the product of the keys, the first written slowest, each point's scene") {
  const SweepPlan plan = parse_sweep_plan(kinetic(
      "\"model.lambda\" = [0.0, 0.5, 2.0]\n\"engine.rtol\" = { from = 1e-8, to = 1e-6, count = 2, spacing = \"log\" }\n"));
  REQUIRE(plan.axes.size() == 2);
  CHECK(plan.axes[0].key == "model.lambda");  // as written, although toml++ sorts keys ("engine" < "model")
  CHECK(plan.axes[1].key == "engine.rtol");
  CHECK(plan.axes[1].log);
  REQUIRE(plan.point_count() == 6);
  CHECK(plan.realizations == 1);
  const double lambdas[] = {0.0, 0.0, 0.5, 0.5, 2.0, 2.0};
  const double rtols[] = {1e-8, 1e-6, 1e-8, 1e-6, 1e-8, 1e-6};
  for (std::size_t p = 0; p < 6; ++p) {
    const auto values = plan.point(p);
    CHECK(values[0].get<double>() == lambdas[p]);
    CHECK(values[1].get<double>() == Approx(rtols[p]).epsilon(1e-12));
    const Scene scene = plan.point_scene(p, 0);
    CHECK(scene.model.lambda(0.0) == lambdas[p]);
    CHECK(scene.engines[0].options["rtol"].get<double>() == Approx(rtols[p]).epsilon(1e-12));
  }
  // The base point is the scene as written; the maps default to the series without observe.final.
  CHECK(plan.scene.model.lambda(0.0) == 0.0);
  CHECK(plan.maps == std::vector<std::string>{"M0", "M2"});
}

TEST_CASE("sweep plan: realization r raises every seed by r, an integer key gets integers from a range") {
  const SweepPlan plan = parse_sweep_plan(particles("\"particles.count\" = { from = 10, to = 30, count = 3 }\nrealizations = 3\n"));
  REQUIRE(plan.point_count() == 3);
  CHECK(plan.realizations == 3);
  CHECK(plan.point(1)[0].is_number_integer());
  for (std::size_t r = 0; r < 3; ++r) {
    const Scene scene = plan.point_scene(2, r);
    CHECK(scene.particles->count == 30);
    CHECK(scene.particles->seed == 7 + r);
  }
  CHECK(plan.maps == std::vector<std::string>{"kinetic_energy"});
  // Without particles.seed the realizations start from the seed a scene without it runs with.
  std::string text = particles("\"particles.count\" = [20]\nrealizations = 2\n");
  text.erase(text.find("seed = 7\n"), 9);
  const SweepPlan unseeded = parse_sweep_plan(text);
  REQUIRE_FALSE(unseeded.scene.particles->seed == 7);
  for (std::size_t r = 0; r < 2; ++r) CHECK(unseeded.point_scene(0, r).particles->seed == unseeded.scene.particles->seed + r);
  // Nothing random to vary: more than one realization is refused.
  CHECK_THAT(error_of(kinetic("\"model.lambda\" = [0.0]\nrealizations = 2\n")), Contains("sweep.realizations") && Contains("no seed"));
}

TEST_CASE("sweep plan: engines are named as the only one, by index or by label") {
  const std::string two = "[[engine]]\nname = \"cvode\"\nrtol = 1e-8\n[[engine]]\nname = \"cvode\"\nlabel = \"loose\"\nrtol = 1e-4\n";
  const SweepPlan by_index = parse_sweep_plan(kinetic("\"engine[1].rtol\" = [1e-5, 1e-6]\n", two));
  CHECK(by_index.point_scene(1, 0).engines[1].options["rtol"].get<double>() == 1e-6);
  CHECK(by_index.point_scene(1, 0).engines[0].options["rtol"].get<double>() == 1e-8);
  const SweepPlan by_label = parse_sweep_plan(kinetic("\"engine[loose].rtol\" = [1e-5]\n", two));
  CHECK(by_label.point_scene(0, 0).engines[1].options["rtol"].get<double>() == 1e-5);
  const SweepPlan by_name = parse_sweep_plan(kinetic("\"engine[cvode].rtol\" = [1e-5]\n", two));  // unlabelled: its name
  CHECK(by_name.point_scene(0, 0).engines[0].options["rtol"].get<double>() == 1e-5);
  CHECK_THAT(error_of(kinetic("\"engine.rtol\" = [1e-5]\n", two)),
             Contains("sweep.\"engine.rtol\"") && Contains("the scene has 2") && Contains("engine[i].X"));
  CHECK_THAT(error_of(kinetic("\"engine[tight].rtol\" = [1e-5]\n", two)), Contains("sweep.\"engine[tight].rtol\"") && Contains("no engine"));
  CHECK_THAT(error_of(kinetic("\"engine[2].rtol\" = [1e-5]\n", two)), Contains("beyond the scene's 2 engines"));
}

TEST_CASE("sweep plan: a key the scene does not have, or a value it refuses, is an error naming the key") {
  // Not a scene key (the particles' volume fraction is under particles.initial, or particles itself).
  CHECK_THAT(error_of(particles("\"particles.volume_fractio\" = [0.05]\n")),
             Contains("sweep.\"particles.volume_fractio\" = 0.05") && Contains("particles.volume_fractio"));
  CHECK_THAT(error_of(kinetic("\"engine.rtoll\" = [1e-6]\n")), Contains("sweep.\"engine.rtoll\"") && Contains("rtoll"));
  CHECK_THAT(error_of(kinetic("\"modl.size\" = [10]\n")), Contains("sweep.\"modl.size\"") && Contains("modl"));
  // A value out of range, a value of the wrong type, a key through a value.
  CHECK_THAT(error_of(kinetic("\"model.size\" = [64, 1]\n")), Contains("sweep.\"model.size\" = 1") && Contains("model.size"));
  CHECK_THAT(error_of(kinetic("\"engine.rtol\" = [\"tight\"]\n")), Contains("sweep.\"engine.rtol\" = tight"));
  CHECK_THAT(error_of(kinetic("\"time.end.x\" = [1.0]\n")), Contains("sweep.\"time.end.x\"") && Contains("not a table"));
  // Forms of [sweep] itself.
  CHECK_THAT(error_of(kinetic("\"model.lambda\" = []\n")), Contains("empty list"));
  CHECK_THAT(error_of(kinetic("\"model.lambda\" = { from = 0, to = 1, count = 3, spacing = \"log\" }\n")), Contains("from"));
  CHECK_THAT(error_of(kinetic("realizations = 1\n")), Contains("at least one swept key"));
  CHECK_THAT(error_of(kinetic("").substr(0, kinetic("").find("[sweep]"))), Contains("sweep") && Contains("required"));
}

TEST_CASE("sweep tables: sweep.csv rows and sweep_mean.csv means and standard errors over the finite values") {
  const SweepPlan plan = parse_sweep_plan(particles("\"engine.restitution\" = [0.5, 0.9]\nrealizations = 3\n"));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Point 0: x = 1, 2, 4 and y = 3, NaN, 5; point 1: one run only, x = 10.
  std::vector<SweepRecord> records;
  const double xs[] = {1, 2, 4}, ys[] = {3, nan, 5};
  for (std::size_t r = 0; r < 3; ++r) records.push_back({0, r, plan.point(0), {{"x", xs[r]}, {"y", ys[r]}}, 0.5, 0});
  records.push_back({1, 0, plan.point(1), {{"x", 10.0}, {"y", nan}}, 0.5, 1});
  CHECK(sweep_csv(plan, records) ==
        "engine.restitution,realization,x,y\n0.5,0,1,3\n0.5,1,2,nan\n0.5,2,4,5\n0.9,0,10,nan\n");
  // Direct: mean 7/3, sample variance ((1-7/3)² + (2-7/3)² + (4-7/3)²)/2 = 7/3, stderr √(7/3/3); y over {3, 5}:
  // mean 4, stderr √2/√2 = 1.
  const std::string mean = sweep_mean_csv(plan, records);
  const std::string header = mean.substr(0, mean.find('\n'));
  CHECK(header == "engine.restitution,runs,x,x_stderr,x_n,y,y_stderr,y_n");
  std::vector<std::string> cells;
  std::string row = mean.substr(mean.find('\n') + 1);
  row = row.substr(0, row.find('\n'));
  for (std::size_t start = 0;;) {
    const std::size_t comma = row.find(',', start);
    cells.push_back(row.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  REQUIRE(cells.size() == 8);
  CHECK(cells[1] == "3");
  CHECK(std::stod(cells[2]) == Approx(7.0 / 3).epsilon(1e-15));
  CHECK(std::stod(cells[3]) == Approx(std::sqrt(7.0 / 9)).epsilon(1e-15));
  CHECK(cells[4] == "3");
  CHECK(std::stod(cells[5]) == 4.0);
  CHECK(std::stod(cells[6]) == Approx(1.0).epsilon(1e-15));
  CHECK(cells[7] == "2");
  CHECK_THAT(mean, Contains("\n0.9,1,10,0,1,nan,nan,0\n"));  // one run: stderr 0; no finite value: NaN
  // Records round-trip through their files; a record of other values or a damaged file is not finished.
  const std::string text = record_file_text(records[1]);
  const auto back = parse_record_file(text, 0, 1, plan.point(0));
  REQUIRE(back);
  CHECK(std::isnan(back->columns[1].second));
  CHECK(back->columns[0].second == 2.0);
  CHECK_FALSE(parse_record_file(text, 0, 1, plan.point(1)));
  CHECK_FALSE(parse_record_file(text, 0, 2, plan.point(0)));
  CHECK_FALSE(parse_record_file(text.substr(0, text.size() / 2), 0, 1, plan.point(0)));
  CHECK(csv_cell("a,b") == "\"a,b\"");
  CHECK(csv_cell("say \"x\"") == "\"say \"\"x\"\"\"");
}

TEST_CASE("sweep records: point, realization and rank are read from JSON integers only, and a float in them is no record") {
  SweepRecord record;
  record.point = 0;
  record.realization = 0;
  record.values = {nlohmann::json(0.5)};
  record.columns = {{"M0", 0.25}};
  record.seconds = 1.5;
  const std::string text = record_file_text(record);
  REQUIRE(parse_record_file(text, 0, 0, record.values));
  const auto with = [&](const std::string& key, const std::string& value) {
    nlohmann::json json = nlohmann::json::parse(text);
    json[key] = nlohmann::json::parse(value);
    return json.dump();
  };
  CHECK(parse_record_file(with("rank", "3"), 0, 0, record.values));
  // A float that truncates to the expected count was read as that count.
  CHECK_FALSE(parse_record_file(with("point", "0.5"), 0, 0, record.values));
  CHECK_FALSE(parse_record_file(with("realization", "0.0"), 0, 0, record.values));
  CHECK_FALSE(parse_record_file(with("rank", "0.5"), 0, 0, record.values));
  // Floats beyond the integer's range: casting them is undefined behaviour (reported under UBSan).
  CHECK_FALSE(parse_record_file(with("point", "1e300"), 0, 0, record.values));
  CHECK_FALSE(parse_record_file(with("realization", "-1e300"), 0, 0, record.values));
  CHECK_FALSE(parse_record_file(with("rank", "1e10"), 0, 0, record.values));
  CHECK_FALSE(parse_record_file(with("rank", "-1"), 0, 0, record.values));
  CHECK_FALSE(parse_record_file(with("rank", "4294967296"), 0, 0, record.values));
}

TEST_CASE("sweep plan: the shipped campaign is the published 245 runs over γ_n and k̃_n, and runs its base point") {
  const SweepPlan plan = load_sweep_plan(std::filesystem::path(AGGKIT_SOURCE_DIR) / "validation/scenes/dem-gravitational-campaign.toml");
  REQUIRE(plan.axes.size() == 2);
  CHECK(plan.axes[0].key == "engine.damping");
  CHECK(plan.axes[1].key == "engine.stiffness_normalized");
  CHECK(plan.axes[0].values.front().get<double>() == 10.0);
  CHECK(plan.axes[0].values.back().get<double>() == 1e5);
  CHECK(plan.axes[1].values.front().get<double>() == 1e5);
  CHECK(plan.axes[1].values.back().get<double>() == 1e8);
  CHECK(plan.point_count() * plan.realizations == 245);  // [Trivino2025, Sec. II.4]
  CHECK(plan.scene.tier == SceneTier::full);
  CHECK(plan.scene.particles->count == 650);
  CHECK(plan.scene.engines[0].options["damping"].get<double>() == 500.0);  // `aggkit run`: the base point
  CHECK(plan.maps == std::vector<std::string>{"components_fraction", "aggregation_time_ff", "fractal_dimension_com"});
  // The final state at stated times: every run goes on to time.end (no stop at T_agg), past 5 t_ff (t_ff ≈ 6.5).
  CHECK(plan.scene.observe.times_ff == std::vector<double>{1.0, 1.5, 2.0, 3.0, 5.0});
  CHECK_FALSE(plan.scene.engines[0].options.contains("stop"));
  CHECK(plan.scene.time.end > 5 * 6.6);
  CHECK(plan.groupings == std::vector<std::vector<std::size_t>>{{0}, {1}});
}

namespace {

// 20 cold self-gravitating DEM spheres with a [sweep] body.
std::string collapse(const std::string& sweep, const std::string& gravity = "gravity = { G = 1.0 }\n") {
  return "name = \"sweep-collapse\"\n[particles]\ndimension = 3\ncount = 20\nradius = 1.0\nmass = 1.0\nboundary = \"open\"\n"
         "initial = { cloud = \"cube\", volume_fraction = 0.05, speed = 0.0 }\n[time]\nend = 1.0\n[[engine]]\nname = \"dem\"\n"
         "restitution = 0.1\ncontact_time = 0.05\n" + gravity +
         "[observe]\nseries = [\"components_fraction\"]\nfinal = [\"components_fraction\", \"fractal_dimension_com\"]\n[sweep]\n"
         "\"engine.restitution\" = [0.1, 0.3]\n\"time.end\" = [1.0, 2.0]\n" + sweep;
}

}  // namespace

TEST_CASE("sweep plan: group_by pools over the other keys, where_not_aggregated sets columns of runs that never aggregated") {
  const SweepPlan plan = parse_sweep_plan(collapse("group_by = [\"time.end\", [\"time.end\", \"engine.restitution\"]]\n"
                                                   "where_not_aggregated = { fractal_dimension_com = 0.0, components_fraction_at_2tff = 1.0 }\n"));
  REQUIRE(plan.axes.size() == 2);  // group_by and where_not_aggregated are not swept keys
  CHECK(plan.groupings == std::vector<std::vector<std::size_t>>{{1}, {1, 0}});
  REQUIRE(plan.not_aggregated.size() == 2);
  CHECK(sweep_map_title(plan, "fractal_dimension_com", {1}) ==
        "sweep-collapse (pooled over engine.restitution); fractal_dimension_com := 0 where aggregation_time is undefined");
  CHECK(sweep_map_title(plan, "components_fraction", {0, 1}) == "sweep-collapse");
  // Pooled table: rows of the grouped values in order of first appearance, means over every run with them.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<SweepRecord> records;
  const double f[] = {2.5, nan, 3.0, 2.0};  // points (0.1, 1), (0.1, 2), (0.3, 1), (0.3, 2)
  const double t[] = {nan, 1.5, nan, 2.0};
  for (std::size_t p = 0; p < 4; ++p) records.push_back({p, 0, plan.point(p), {{"fractal_dimension_com", f[p]}, {"aggregation_time", t[p]}}, 0, 0});
  CHECK(sweep_pooled_csv(plan, records, {1}) ==
        "time.end,runs,fractal_dimension_com,fractal_dimension_com_stderr,fractal_dimension_com_n,aggregation_time,aggregation_time_stderr,"
        "aggregation_time_n\n1,2,2.75,0.25,2,nan,nan,0\n2,2,2,0,1,1.75,0.25,2\n");
  // Filled: F := 0 where aggregation_time is NaN (points 0 and 2), kept where it aggregated.
  const std::vector<SweepRecord> filled = fill_not_aggregated(plan, records);
  CHECK(filled[0].columns[0].second == 0.0);
  CHECK(std::isnan(filled[1].columns[0].second));
  CHECK(filled[2].columns[0].second == 0.0);
  CHECK(filled[3].columns[0].second == 2.0);
  // Bad input, naming the key.
  CHECK_THAT(error_of(collapse("group_by = [\"engine.damping\"]\n")), Contains("sweep.group_by[0]") && Contains("a swept key"));
  CHECK_THAT(error_of(collapse("group_by = [[\"time.end\", \"time.end\"]]\n")), Contains("sweep.group_by[0]") && Contains("once"));
  CHECK_THAT(error_of(collapse("group_by = [\"time.end\", [\"time.end\"]]\n")), Contains("sweep.group_by[1]") && Contains("each grouping once"));
  CHECK_THAT(error_of(collapse("group_by = []\n")), Contains("sweep.group_by") && Contains("a list of groupings"));
  CHECK_THAT(error_of(collapse("group_by = [3]\n")), Contains("sweep.group_by[0] = 3"));
  CHECK_THAT(error_of(collapse("where_not_aggregated = { fractal_dimensio = 0.0 }\n")),
             Contains("sweep.where_not_aggregated.fractal_dimensio") && Contains("observe.final"));
  CHECK_THAT(error_of(collapse("where_not_aggregated = { fractal_dimension_com = \"zero\" }\n")),
             Contains("sweep.where_not_aggregated.fractal_dimension_com"));
  CHECK_THAT(error_of(collapse("where_not_aggregated = 0.0\n")), Contains("sweep.where_not_aggregated") && Contains("table"));
  CHECK_THAT(error_of(collapse("where_not_aggregated = { fractal_dimension_com = 0.0 }\n", "")), Contains("dem with gravity"));
}

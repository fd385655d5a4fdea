// The ed engine through the harness: [particles] and observe.final parsing, bad input, the output contract
// (series.csv header and values, final.json keys, stderr with realizations) and the physics it reports.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <set>

#include <nlohmann/json.hpp>

#include "analysis/input_error.hpp"
#include "tests/validation/scene_fixture.hpp"
#include "validation/harness/harness.hpp"

using namespace aggkit;
using Catch::Matchers::Contains;

namespace {

std::string ed_scene(const std::string& particles_extra = "", const std::string& engine_extra = "stop = \"one_cluster\"\n",
                     const std::string& observe = "series = [\"clusters\", \"kinetic_energy\", \"mean_cluster_size\", \"M0\", \"M1\"]\n"
                                                  "final = [\"clusters\", \"contacts\", \"contacts_with_self\", \"fractal_dimension_mass\", \"aspect_ratio\", \"pair_distribution\"]\n") {
  return "name = \"ed-test\"\n[particles]\ndimension = 2\ncount = 100\nradius = 0.5\nvolume_fraction = 0.2\n"
         "boundary = \"reflecting\"\ninitial = { lattice = \"square\", speed = 1.0, directions = \"uniform\" }\n" +
         particles_extra + "\n[time]\nend = 5.0\noutputs = [1.0, 2.0, 5.0]\n\n[[engine]]\nname = \"ed\"\n" + engine_extra +
         "\n[observe]\n" + observe;
}

// `text` with its first `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  text.replace(text.find(from), from.size(), to);
  return text;
}

RunOptions quiet(const std::filesystem::path& out) { return aggkit::testing::quiet_run(out); }

void check_bad(const std::string& text, const std::string& key, const std::string& value) {
  INFO(text);
  try {
    aggkit::testing::parse_checked(text);
    FAIL("no InputError");
  } catch (const InputError& e) {
    CHECK(e.key() == key);
    CHECK_THAT(std::string(e.what()), Contains(value));
  }
}

}  // namespace

TEST_CASE("ed: series and final.json follow the contract and the physics", "[ed][harness]") {
  const auto out = aggkit::testing::scratch_folder("ed-contract");
  const Scene scene = aggkit::testing::parse_checked(ed_scene("realizations = 3\nseed = 5\n"));
  REQUIRE(scene.particles);
  CHECK_FALSE(scene.has_model);
  const RunResult result = run_scene(scene, quiet(out));
  REQUIRE(result.records.size() == 1);
  REQUIRE(result.records[0].completed());
  // Three realizations: every series observable has its standard error over them.
  CHECK(aggkit::testing::first_line(out / "ed" / "series.csv") ==
        "t,clusters,kinetic_energy,mean_cluster_size,M0,M1,clusters_stderr,kinetic_energy_stderr,"
        "mean_cluster_size_stderr,M0_stderr,M1_stderr");
  const auto& values = result.records[0].values;
  REQUIRE(values.size() == 3);
  double previous_energy = 50.0, previous_clusters = 100.0;  // ½ N v² and N at the start
  for (const auto& row : values) {
    CHECK(row[0] <= previous_clusters);  // merging only: the cluster count never grows
    previous_clusters = row[0];
    CHECK(row[1] <= previous_energy * (1 + 1e-12));  // inelastic merging: energy never grows
    previous_energy = row[1];
    CHECK(row[2] == Approx(100.0 / row[0]).epsilon(0.5));  // N/C per realization, averaged: close to N/mean C
    CHECK(row[3] == Approx(row[0] / 100.0).epsilon(1e-12));  // M0 = C/N
    CHECK(row[4] == Approx(1.0).epsilon(1e-12));             // M1 = 1: mass conservation
  }
  std::ifstream in(out / "ed" / "final.json");
  const auto final = nlohmann::json::parse(in);
  for (const char* key : {"clusters", "contacts", "fractal_dimension_mass", "aspect_ratio", "events", "wall_seconds",
                          "momentum_drift", "clusters_stderr", "contacts_stderr", "events_stderr"})
    CHECK(final.contains(key));
  CHECK(final["clusters"].get<double>() == 1.0);
  CHECK(final["clusters_stderr"].get<double>() == 0.0);
  CHECK(final["realizations"].get<int>() == 3);
  // Momentum plus wall impulse is conserved to round-off (relative to Σ m|v|).
  CHECK(final["momentum_drift"].get<double>() < 1e-13);
  // Hit-and-stick merging makes one contact per merge: at least the tree value 2(N−1)/(N·6) = 0.33.
  CHECK(final["contacts"].get<double>() >= 2.0 * 99 / 100 / 6 - 1e-12);
  // The published reading (i = j counted, analysis/shape.hpp) adds exactly 1/N_max to each realization.
  CHECK(final["contacts_with_self"].get<double>() == Approx(final["contacts"].get<double>() + 1.0 / 6).epsilon(1e-12));
  CHECK_FALSE(std::filesystem::exists(out / "ed" / "final.vtu"));  // snapshots not requested
  // The pair distribution, a profile: its own CSV (mean of the 3 realizations and its standard error).
  CHECK_FALSE(final.contains("pair_distribution"));
  CHECK(aggkit::testing::first_line(out / "ed" / "pair_distribution.csv") == "r,P,P_stderr");
  std::vector<double> r, p;
  for (const auto& row : aggkit::testing::csv_rows(out / "ed" / "pair_distribution.csv")) {
    REQUIRE(row.size() == 3);
    CHECK(row[2] >= 0);
    r.push_back(row[0]);
    p.push_back(row[1]);
  }
  REQUIRE(r.size() == 90);
  CHECK(r.front() == Approx(0.5 * (2 + 18.0 / 90)).epsilon(1e-12));  // R = 0.5: radii on (2R, 20R]
  CHECK(r.back() == Approx(0.5 * 20).epsilon(1e-12));
  CHECK(std::is_sorted(p.begin(), p.end()));
  // One cluster of N = 100 from hit-and-stick: at least its N − 1 contacts within 2.2R, i.e. P ≥ 2(N−1)/N,
  // and never more than the N − 1 other particles.
  CHECK(p.front() >= 2.0 * 99 / 100 - 1e-12);
  CHECK(p.back() <= 99.0);
}

TEST_CASE("ed: no merge before the lattice gaps can close, then the pairs' own collision rate", "[ed][harness]") {
  // The square lattice of the scene: box L = R √(Nπ/φ) = 19.82, spacing d = L/10 = 1.98, gaps d − 2R = 0.98
  // between the 180 neighbour pairs (diagonal pairs and walls are farther: none is reached before t = 0.9 and
  // 0.49), all speeds 1 in uniform directions. No pair closes faster than 2: no merge before t = 0.491 in any
  // realization. Just after, the merges are those of independent neighbour pairs: E[merges by t] = 180 P(a pair
  // with unit velocities in uniform directions, d apart, touches by t), integrated below by Monte Carlo on the
  // pair's own quadratic (not the engine's). At t = 0.55 that is 4.4; 40 realizations give it to ±0.3 (one
  // standard error), and the engine measured 5.1 and 4.0 for seeds 8 and 9. A contact distance 25 % too large
  // in the engine's collision time gives 7.1 and 6.0.
  const double d = 0.5 * std::sqrt(100 * M_PI / 0.2) / 10, t = 0.55;
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> angle(0.0, 2 * M_PI);
  const int samples = 1000000;
  int touched = 0;
  for (int k = 0; k < samples; ++k) {
    const double a = angle(random), b = angle(random);
    const double wx = std::cos(b) - std::cos(a), wy = std::sin(b) - std::sin(a);  // j − i, j at (d, 0) from i
    const double closing = -d * wx, c = d * d - 1.0, w2 = wx * wx + wy * wy;
    const double discriminant = closing * closing - w2 * c;
    if (closing > 0 && discriminant >= 0 && c / (closing + std::sqrt(discriminant)) < t) ++touched;
  }
  const double expected = 180.0 * touched / samples;
  const auto out = aggkit::testing::scratch_folder("ed-first-contact");
  std::string scene = replaced(ed_scene("realizations = 40\nseed = 8\n", "", "series = [\"clusters\"]\n"),
                               "outputs = [1.0, 2.0, 5.0]", "outputs = [0.48, 0.55]");
  scene = replaced(scene, "end = 5.0", "end = 0.55");
  const RunResult result = run_scene(aggkit::testing::parse_checked(scene), quiet(out));
  REQUIRE(result.records[0].completed());
  const auto& values = result.records[0].values;
  const auto& errors = result.records[0].standard_errors;
  REQUIRE(values.size() == 2);
  CHECK(values[0][0] == 100.0);
  CHECK(errors[0][0] == 0.0);
  const double merges = 100.0 - values[1][0];
  INFO("merges by t = 0.55: " << merges << " ± " << errors[1][0] << ", independent pairs " << expected);
  CHECK(expected == Approx(4.38).epsilon(0.03));
  // 4 standard errors, and 0.3 for what independent pairs leave out (a third particle, a wall).
  CHECK(std::abs(merges - expected) <= 4 * errors[1][0] + 0.3);
}

TEST_CASE("ed: size distribution (PDF and CDF) at a chosen time", "[ed][harness]") {
  const auto out = aggkit::testing::scratch_folder("ed-distribution");
  run_scene(aggkit::testing::parse_checked(ed_scene("seed = 2\n", "stop = \"one_cluster\"\n",
                                 "series = [\"M0\"]\ndistributions = [1.0]\nfinal = [\"clusters\"]\n")),
            quiet(out));
  CHECK(aggkit::testing::first_line(out / "ed" / "distribution.csv") == "t,k,n,cdf");
  // n_k per initial particle at t = 1 up to the largest size: Σ k n_k = 1 (mass), Σ n_k = M0 = C/N as in series.csv,
  // and the CDF is the running sum of n_k over M0, rising to 1.
  std::vector<double> n, cdf;
  for (const auto& row : aggkit::testing::csv_rows(out / "ed" / "distribution.csv")) {
    REQUIRE(row.size() == 4);
    CHECK(row[0] == 1.0);
    CHECK(row[1] == double(n.size() + 1));
    n.push_back(row[2]);
    cdf.push_back(row[3]);
  }
  REQUIRE(n.size() >= 2);  // rows k = 1 .. the largest cluster's size
  CHECK(n.back() > 0);
  double mass = 0, m0 = 0;
  for (std::size_t k = 1; k <= n.size(); ++k) {
    mass += double(k) * n[k - 1];
    m0 += n[k - 1];
  }
  CHECK(mass == Approx(1.0).epsilon(1e-12));
  CHECK(n[0] < m0);  // some clusters have formed by t = 1 at ν = 0.2
  double running = 0;
  for (std::size_t k = 0; k < n.size(); ++k) {
    running += n[k];
    CHECK(cdf[k] == Approx(running / m0).epsilon(1e-12));
  }
  CHECK(cdf.back() == Approx(1.0).epsilon(1e-12));
  const auto series = aggkit::testing::csv_rows(out / "ed" / "series.csv");
  REQUIRE(!series.empty());
  CHECK(series[0][0] == 1.0);
  CHECK(series[0][1] == Approx(m0).epsilon(1e-12));  // M0 at t = 1
}

TEST_CASE("ed: thermalize runs the elastic stage first, then sticking from t = 0", "[ed][harness]") {
  const auto out = aggkit::testing::scratch_folder("ed-thermalize");
  const RunResult result =
      run_scene(aggkit::testing::parse_checked(ed_scene("thermalize = 4\n", "stop = \"one_cluster\"\n",
                                     "series = [\"clusters\", \"kinetic_energy\"]\nfinal = [\"clusters\"]\n")),
                quiet(out));
  REQUIRE(result.records[0].completed());
  // Elastic collisions conserve energy, so sticking starts with ½ N v² = 50 and loses energy from there.
  CHECK(result.records[0].values.front()[1] < 50.0);
  std::ifstream in(out / "ed" / "final.json");
  const auto final = nlohmann::json::parse(in);
  CHECK(final["clusters"].get<double>() == 1.0);
  // Every one of the 100 particles collided at least 4 times, two particles per collision.
  CHECK(final["thermalization_collisions"].get<double>() >= 4 * 100 / 2);
  CHECK(final["momentum_drift"].get<double>() < 1e-13);
}

TEST_CASE("ed: without stop the run ends at time.end, { clusters = K } stops at K", "[ed][harness]") {
  const auto out = aggkit::testing::scratch_folder("ed-stop");
  const RunResult by_time = run_scene(aggkit::testing::parse_checked(ed_scene("", "", "series = [\"clusters\"]\n")), quiet(out));
  REQUIRE(by_time.records[0].completed());
  CHECK(by_time.records[0].values.back()[0] > 1.0);  // 100 particles do not reach one cluster by t = 5
  const RunResult by_count =
      run_scene(aggkit::testing::parse_checked(ed_scene("", "stop = { clusters = 50 }\n", "series = [\"clusters\"]\nfinal = [\"clusters\"]\n")),
                quiet(out));
  std::ifstream in(out / "ed" / "final.json");
  CHECK(nlohmann::json::parse(in)["clusters"].get<double>() == 50.0);
}

TEST_CASE("ed: snapshots write final.vtu", "[ed][harness]") {
  const auto out = aggkit::testing::scratch_folder("ed-snapshot");
  run_scene(aggkit::testing::parse_checked(ed_scene("", "stop = \"one_cluster\"\n", "series = [\"clusters\"]\nsnapshots = true\n")), quiet(out));
  CHECK(std::filesystem::exists(out / "ed" / "final.vtu"));
  CHECK(std::filesystem::exists(out / "ed" / "final.json"));
}

TEST_CASE("ed: bad [particles], stop and observe input name the key", "[ed][harness]") {
  check_bad(ed_scene("", "stop = \"never\"\n"), "engine[0].stop", "never");
  check_bad(ed_scene("", "stop = { clusters = 1000 }\n"), "engine[0].stop.clusters", "1000");
  check_bad(ed_scene("thermalize = -1\n"), "particles.thermalize", "-1");
  check_bad(ed_scene("", "", "series = [\"clusters\"]\nfinal = [\"temperature\"]\n"), "observe.final[0]", "temperature");
  const std::string base = ed_scene();
  const auto replace = [&](const std::string& from, const std::string& to) { return replaced(base, from, to); };
  check_bad(replace("boundary = \"reflecting\"", "boundary = \"sticky\""), "particles.boundary", "sticky");
  check_bad(replace("dimension = 2", "dimension = 4"), "particles.dimension", "4");
  check_bad(replace("volume_fraction = 0.2", "volume_fraction = 0.9"), "particles.volume_fraction", "0.9");
  check_bad(replace("volume_fraction = 0.2", "volume_fraction = 0.2\nbox = 10.0"), "particles.box", "10");
  check_bad(replace("directions = \"uniform\"", "directions = \"gaussian\""), "particles.initial.directions", "gaussian");
  check_bad(replace("lattice = \"square\"", "lattice = \"hexagonal\""), "particles.initial.lattice", "hexagonal");
  // A kinetic engine needs [model]; the ed engine needs [particles].
  check_bad(replace("name = \"ed\"", "name = \"cvode\""), "engine[0].name", "cvode");
  check_bad("name = \"x\"\n[model]\nkernel = { name = \"constant\" }\nsize = 10\n[time]\nend = 1.0\n[[engine]]\nname = \"ed\"\n"
            "[observe]\nseries = [\"M0\"]\n",
            "engine[0].name", "ed");
}

TEST_CASE("ed: outputs are unchanged from the recorded ones, file for file", "[ed][harness][runner]") {
  // tests/validation/data/ed-reference/: the outputs of two fixed-seed runs (full precision, one
  // realization), first written by the engine's own realization loop before the particle runner existed.
  // A pin, not physics (the other ed tests check the physics): any change of the trajectories or of what
  // is written shows here. A change made on purpose regenerates the files and says why in its commit. The
  // folders must hold the same files: a missing or an extra output fails.
  const auto data = std::filesystem::path(AGGKIT_SOURCE_DIR) / "tests" / "validation" / "data" / "ed-reference";
  const auto files = [](const std::filesystem::path& folder) {
    std::set<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(folder))
      if (entry.path().extension() == ".csv" || entry.path().extension() == ".json") names.insert(entry.path().filename().string());
    return names;
  };
  for (const std::string name : {"reflecting-2d", "periodic-3d"}) {
    INFO(name);
    const auto out = aggkit::testing::scratch_folder("ed-reference-" + name);
    const RunResult result = run_scene(load_scene(data / (name + ".toml")), quiet(out));
    REQUIRE(result.exit_code == 0);
    const std::set<std::string> written = files(out / "ed");
    REQUIRE(written == files(data / name));
    REQUIRE(written.count("series.csv") == 1);
    REQUIRE(written.count("final.json") == 1);
    using aggkit::testing::read_text;
    for (const std::string& file : written) {
      INFO(file);
      if (file != "final.json") {
        CHECK(read_text(out / "ed" / file) == read_text(data / name / file));
        continue;
      }
      auto now = nlohmann::json::parse(read_text(out / "ed" / file));
      auto before = nlohmann::json::parse(read_text(data / name / file));
      now.erase("wall_seconds");  // timing: the one value that may differ
      before.erase("wall_seconds");
      CHECK(now.dump(1) == before.dump(1));
    }
  }
}

TEST_CASE("ed: realizations on threads give the same outputs as one after the other", "[ed][harness][runner]") {
  const std::string observe = "series = [\"clusters\", \"kinetic_energy\", \"M2\"]\nfinal = [\"contacts\", \"pair_distribution\"]\n";
  const auto serial = aggkit::testing::scratch_folder("ed-threads-1");
  const auto threaded = aggkit::testing::scratch_folder("ed-threads-3");
  run_scene(aggkit::testing::parse_checked(ed_scene("realizations = 4\nseed = 3\n", "stop = { clusters = 10 }\n", observe)),
            quiet(serial));
  run_scene(aggkit::testing::parse_checked(
                ed_scene("realizations = 4\nseed = 3\n", "stop = { clusters = 10 }\nthreads = 3\n", observe)),
            quiet(threaded));
  using aggkit::testing::read_text;
  CHECK(read_text(serial / "ed" / "series.csv") == read_text(threaded / "ed" / "series.csv"));
  CHECK(read_text(serial / "ed" / "pair_distribution.csv") == read_text(threaded / "ed" / "pair_distribution.csv"));
  auto a = nlohmann::json::parse(read_text(serial / "ed" / "final.json"));
  auto b = nlohmann::json::parse(read_text(threaded / "ed" / "final.json"));
  for (auto* j : {&a, &b}) j->erase("wall_seconds"), j->erase("wall_seconds_stderr");
  CHECK(a == b);
  CHECK(a.contains("contacts_stderr"));
}

TEST_CASE("ed: a rerun into the same folder leaves no file the new scene does not write", "[ed][harness][runner]") {
  const auto out = aggkit::testing::scratch_folder("ed-rerun");
  run_scene(aggkit::testing::parse_checked(ed_scene()), quiet(out));  // asks for pair_distribution
  REQUIRE(std::filesystem::exists(out / "ed" / "pair_distribution.csv"));
  run_scene(aggkit::testing::parse_checked(ed_scene("", "stop = \"one_cluster\"\n", "series = [\"clusters\"]\n")), quiet(out));
  CHECK_FALSE(std::filesystem::exists(out / "ed" / "pair_distribution.csv"));
  CHECK(std::filesystem::exists(out / "ed" / "final.json"));
}

TEST_CASE("ed: observables a kinetic engine cannot give are refused for it, naming the observable", "[ed][harness]") {
  aggkit::testing::SceneText text;
  text.observe = "series = [\"M0\", \"kinetic_energy\"]\n";
  text.compare = "";
  try {
    aggkit::testing::parse_checked(text.text());
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(e.key() == "observe.series[1]");
    CHECK_THAT(std::string(e.what()), Contains("cvode") && Contains("particle velocities"));
  }
}

TEST_CASE("ed: [particles] forms the engine cannot use are refused naming the key, the others run", "[ed][particles]") {
  const std::string base = ed_scene();
  const auto replace = [&](const std::string& from, const std::string& to) { return replaced(base, from, to); };
  const std::string cloud = replace("lattice = \"square\", speed = 1.0", "cloud = \"cube\", speed = 1.0");
  check_bad(replaced(cloud, "radius = 0.5", "radius = { distribution = \"uniform\", min = 0.4, max = 0.6 }"),
            "particles.radius", "distribution");
  check_bad(replace("radius = 0.5", "radius = 0.5\nmass = { distribution = \"uniform\", min = 1, max = 2 }"),
            "particles.mass", "unequal");
  check_bad(replace("speed = 1.0", "speed = 0"), "particles.initial.speed", "0");
  check_bad(replace("volume_fraction = 0.2\nboundary = \"reflecting\"\ninitial = { lattice = \"square\", speed = 1.0, "
                    "directions = \"uniform\" }",
                    "boundary = \"open\"\ninitial = { cloud = \"sphere\", volume_fraction = 0.2 }"),
            "particles.boundary", "open");

  // A random cloud filling the box, and equal masses from a density: both are forms ED can run.
  const auto out = aggkit::testing::scratch_folder("ed-cloud");
  const std::string heavy = replaced(cloud, "radius = 0.5", "radius = 0.5\nmass = { density = 2.0 }");
  const RunResult run = run_scene(aggkit::testing::parse_checked(heavy), quiet(out));
  REQUIRE(run.records[0].completed());
  const auto final = nlohmann::json::parse(aggkit::testing::read_text(out / "ed" / "final.json"));
  CHECK(final["clusters"].get<double>() == 1.0);  // stop = "one_cluster"
  CHECK(final["momentum_drift"].get<double>() < 1e-12);
  // m = ρ π R² = 2π/4 per disc: the kinetic energy at t = 1 is at most ½ N m v² = 100 π / 4.
  CHECK(run.records[0].values.front()[1] <= 100 * 3.14159265358979 / 4 * (1 + 1e-12));
  CHECK(run.records[0].values.front()[1] > 0.5 * 100 * 3.14159265358979 / 4 * 0.1);
}

TEST_CASE("ed: extreme but valid scales finish, scales doubles cannot resolve are refused", "[ed][input]") {
  const std::string base = ed_scene();
  const auto replace = [&](const std::string& from, const std::string& to) { return replaced(base, from, to); };
  // Collisions ~1e10 time.end apart: the run to one cluster goes on in doubling chunks and ends.
  const auto out = aggkit::testing::scratch_folder("ed-slow");
  const RunResult slow = run_scene(aggkit::testing::parse_checked(replace("speed = 1.0", "speed = 1e-10")), quiet(out));
  REQUIRE(slow.records[0].completed());
  const auto final = nlohmann::json::parse(aggkit::testing::read_text(out / "ed" / "final.json"));
  CHECK(final["clusters"].get<double>() == 1.0);
  CHECK(final["stop_time"].get<double>() > 1e9);
  check_bad(replace("speed = 1.0", "speed = 1e300"), "particles.initial.speed", "1e+300");
  check_bad(replace("volume_fraction = 0.2", "box = 1e300"), "particles.box", "1e+300");
}

TEST_CASE("ed: the wall-time budget stops a run that would take too long, as a failed engine", "[ed][harness]") {
  const auto out = aggkit::testing::scratch_folder("ed-budget");
  const std::string text = "name = \"budget\"\n[particles]\ndimension = 2\ncount = 40000\nradius = 0.5\nvolume_fraction = 0.2\n"
                           "boundary = \"periodic\"\n[time]\nend = 1000.0\n[[engine]]\nname = \"ed\"\nstop = \"one_cluster\"\n"
                           "max_wall_seconds = 1e-6\n[observe]\nseries = [\"clusters\"]\n";
  const RunResult result = run_scene(aggkit::testing::parse_checked(text), quiet(out));
  REQUIRE(result.records.size() == 1);
  REQUIRE_FALSE(result.records[0].completed());
  CHECK_THAT(*result.records[0].failure, Contains("max_wall_seconds"));
  CHECK(result.exit_code == 1);
}

TEST_CASE("ed: [compare] final tolerances compare final.json means with their standard errors", "[ed][harness]") {
  // Two ED engines on the same realizations (only the broad-phase cell count differs): identical physics, so
  // every final value agrees exactly and passes any tolerance; a tolerance on a value the engine does not
  // report fails, and a final tolerance names only observe.final numbers.
  const std::string text =
      "name = \"ed-vs-ed\"\n[particles]\ndimension = 2\ncount = 100\nradius = 0.5\nvolume_fraction = 0.2\n"
      "boundary = \"reflecting\"\nrealizations = 3\n[time]\nend = 2.0\n[[engine]]\nname = \"ed\"\nstop = \"one_cluster\"\n"
      "[[engine]]\nname = \"ed\"\nlabel = \"ed-cells\"\ncells = 7\nstop = \"one_cluster\"\n[observe]\nseries = [\"clusters\"]\n"
      "final = [\"contacts\", \"fractal_dimension_mass\", \"pair_distribution\"]\n[compare]\nreference = \"ed\"\n"
      "final = { contacts = { relative = 0, stderr = 0 }, fractal_dimension_mass = 1e-12 }\n";
  const auto out = aggkit::testing::scratch_folder("ed-final-compare");
  const RunResult result = run_scene(aggkit::testing::parse_checked(text), quiet(out));
  CHECK(result.exit_code == 0);
  int finals = 0;
  for (const auto& c : result.comparisons)
    if (c.final_state) {
      ++finals;
      CHECK(c.pass);
      CHECK(c.max_relative_error == 0.0);
    }
  CHECK(finals == 2);  // the profile is not compared as a number
  const auto summary = nlohmann::json::parse(aggkit::testing::read_text(out / "summary.json"));
  CHECK(summary["comparisons"].back()["kind"] == "final");
  check_bad(replaced(text, "fractal_dimension_mass = 1e-12", "pair_distribution = 0.1"), "compare.final.pair_distribution",
            "0.1");
}

TEST_CASE("ed: the shipped scene against the Smoluchowski equation with the 2-D ballistic kernel passes",
          "[ed][harness][physics]") {
  // Dilute ED (ν = 0.005, Maxwellian start) against CVODE with kernel ballistic2d in the kinetic time
  // τ = n0 K0 t (the scene's opening comment derives the units and the measured window of agreement).
  const auto out = aggkit::testing::scratch_folder("ed-vs-smoluchowski");
  const Scene scene = load_scene(std::filesystem::path(AGGKIT_SOURCE_DIR) / "validation/scenes/ed-vs-smoluchowski-2d.toml");
  const RunResult result = run_scene(scene, aggkit::testing::quiet_run(out));
  REQUIRE(result.records.size() == 2);
  CHECK(result.pass);
  REQUIRE(result.comparisons.size() >= 2);
  // At the first output (τ = 0.1, 12 % of the discs merged) the rates are those of the disc gas itself:
  // measured agreement 0.1 %, within one standard error (0.2 %).
  const EngineRecord& ed = result.records[1];
  const EngineRecord& kinetic = result.records[0];
  CHECK(std::abs(ed.values[0][0] - kinetic.values[0][0]) <= 3 * ed.standard_errors[0][0]);
}

// The [particles] section: every form parses into the ParticleSystem it describes, and every bad value is an
// InputError naming the full scene key and showing the value (some also end to end through `aggkit run`).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <sys/wait.h>

#include "analysis/input_error.hpp"
#include "tests/validation/scene_fixture.hpp"
#include "validation/scene/scene.hpp"

using namespace aggkit;
using Catch::Matchers::Contains;

namespace {

// A valid kinetic scene (the fixture) with a [particles] section: parsed whatever the particle engines
// accept, so only the section's own rules apply.
std::string with_particles(const std::string& particles) {
  return aggkit::testing::SceneText{}.text() + "\n[particles]\n" + particles;
}

ParticleSystem particles_of(const std::string& particles) {
  const Scene scene = parse_scene(with_particles(particles));
  REQUIRE(scene.particles);
  return *scene.particles;
}

void check_bad(const std::string& particles, const std::string& key, const std::string& value) {
  INFO(particles);
  try {
    parse_scene(with_particles(particles));
    FAIL("no InputError");
  } catch (const InputError& e) {
    CHECK(e.key() == key);
    CHECK_THAT(std::string(e.what()), Contains(value));
  }
}

std::filesystem::path write_csv(const std::filesystem::path& file, const std::string& text) {
  return aggkit::testing::write_text(file, text);
}

const std::string two_d = "dimension = 2\ncount = 200\nboundary = \"periodic\"\n";

}  // namespace

TEST_CASE("particles: today's lattice form keeps its box and start", "[particles][scene]") {
  const ParticleSystem s = particles_of("dimension = 2\ncount = 100\nradius = 0.5\nvolume_fraction = 0.2\n"
                                        "boundary = \"reflecting\"\ninitial = { lattice = \"square\", speed = 2.0, "
                                        "components = \"uniform\" }\nthermalize = 3\nseed = 4\nrealizations = 2\n");
  CHECK(s.start_kind() == ParticleSystem::StartKind::lattice);
  CHECK(s.box.side[0] == box_side_for_volume_fraction(2, 100, 0.5, 0.2));
  CHECK(s.equal_radii());
  CHECK(s.mean_radius() == 0.5);
  CHECK(s.equal_masses());
  CHECK(s.mean_mass() == 1.0);
  CHECK(s.velocities == VelocityLaw::uniform_components);
  CHECK(s.speed == 2.0);
  CHECK(s.thermalize == 3);
  CHECK(s.realizations == 2);
  // No initial table: the lattice at unit speed.
  const ParticleSystem d = particles_of("dimension = 3\ncount = 27\nradius = 0.5\nbox = 6.0\nboundary = \"periodic\"\n");
  CHECK(d.start_kind() == ParticleSystem::StartKind::lattice);
  CHECK(d.speed == 1.0);
  CHECK(d.box.side == Vector3{6, 6, 6});
}

TEST_CASE("particles: radius and mass laws, clouds and open space parse", "[particles][scene]") {
  // A normal radius with a density mass law, a cloud filling a periodic box of volume fraction 0.2.
  ParticleSystem s = particles_of(two_d + "radius = { distribution = \"normal\", mean = 1.0, sd = 0.1, min = 0.7 }\n"
                                          "mass = { density = 2.0 }\nvolume_fraction = 0.2\ninitial = { cloud = \"cube\" }\n");
  CHECK(s.radius_law.distribution == Distribution::normal);
  CHECK(s.radius_law.min == 0.7);
  CHECK(std::isinf(s.radius_law.max));
  CHECK(s.mass_law.density == 2.0);
  CHECK(s.start_kind() == ParticleSystem::StartKind::cloud);
  // The box side from the expected particle volume N·E[πR²] = N π (m² + s²) (truncation 3 sd below: ~1e-3).
  CHECK(s.box.side[0] == Approx(std::sqrt(200 * std::numbers::pi * 1.01 / 0.2)).epsilon(2e-3));
  CHECK(s.volume_fraction() == Approx(0.2).epsilon(1e-12));
  CHECK(s.mean_mass() == Approx(2.0 * std::numbers::pi * 1.01).epsilon(2e-3));

  // A lognormal radius and uniform masses, a sphere cloud of diameter 40 in a reflecting box, cold.
  s = particles_of("dimension = 3\ncount = 50\nboundary = \"reflecting\"\nbox = 50.0\n"
                   "radius = { distribution = \"lognormal\", mean = 1.0, sd = 0.2, max = 1.6 }\n"
                   "mass = { distribution = \"uniform\", min = 1.0, max = 2.0 }\n"
                   "initial = { cloud = \"sphere\", size = 40.0, speed = 0.0 }\n");
  CHECK(s.radius_law.distribution == Distribution::lognormal);
  CHECK(s.radius_law.max == 1.6);
  CHECK(s.mass_law.law.distribution == Distribution::uniform);
  CHECK(s.mean_mass() == Approx(1.5).epsilon(1e-12));
  CHECK(s.cold());
  CHECK(s.cloud_region().size == 40.0);
  CHECK(s.cloud_region().centre == Vector3{25, 25, 25});

  // Open space: a sphere of volume fraction 0.1 around the origin, uniform radii, uniform components.
  s = particles_of("dimension = 3\ncount = 100\nboundary = \"open\"\n"
                   "radius = { distribution = \"uniform\", min = 0.5, max = 1.0 }\n"
                   "initial = { cloud = \"sphere\", volume_fraction = 0.1, components = \"uniform\" }\n");
  CHECK(s.box.boundary == Boundary::open);
  CHECK(s.volume_fraction() == 0.1);
  CHECK(s.velocities == VelocityLaw::uniform_components);
  const ParticleStart start = s.initial_state(0);
  for (std::size_t i = 0; i < s.count; ++i) CHECK(norm(start.positions[i]) <= s.cloud_region().size / 2 - start.radii[i] + 1e-12);
  // An open cube of side 30, mass a number.
  s = particles_of("dimension = 2\ncount = 100\nboundary = \"open\"\nradius = 0.5\nmass = 3.0\n"
                   "initial = { cloud = \"cube\", size = 30.0 }\n");
  CHECK(s.cloud_region().size == 30.0);
  CHECK(s.mean_mass() == 3.0);
}

TEST_CASE("particles: a start file relative to the scene file's folder", "[particles][scene]") {
  const auto folder = aggkit::testing::scratch_folder("particles-start-file");
  std::filesystem::create_directories(folder / "starts");
  write_csv(folder / "starts" / "three.csv", "x,y,vx,vy,radius,mass\n1,1,0.5,0,0.5,1\n3,1,-0.5,0,0.5,1\n\n5,5,0,1,1,8\n");
  const std::string body = "name = \"file\"\n[particles]\ndimension = 2\nbox = 10.0\nboundary = \"reflecting\"\n"
                           "initial = { file = \"starts/three.csv\" }\n[time]\nend = 1.0\n[[engine]]\nname = \"ed\"\n"
                           "[observe]\nseries = [\"clusters\"]\n";
  const Scene scene = load_scene(aggkit::testing::write_text(folder / "scene.toml", body));
  REQUIRE(scene.particles);
  const ParticleSystem& s = *scene.particles;
  CHECK(s.start_kind() == ParticleSystem::StartKind::file);
  CHECK(s.count == 3);
  CHECK_FALSE(s.equal_radii());
  CHECK(s.mean_radius() == Approx(2.0 / 3));
  CHECK(s.mean_mass() == Approx(10.0 / 3));
  const ParticleStart start = s.initial_state(1);
  CHECK(start.positions[2] == Vector3{5, 5, 0});
  CHECK(start.velocities[0] == Vector3{0.5, 0, 0});
  CHECK(std::get<FileStart>(s.start).file.lines[2] == 5);  // the blank line 4 is skipped
  // As text: an absolute path as it is; count, when given, must match.
  const std::string absolute = (folder / "starts" / "three.csv").string();
  CHECK(particles_of("dimension = 2\ncount = 3\nbox = 10.0\nboundary = \"periodic\"\ninitial = { file = \"" + absolute + "\" }\n").count == 3);
}

TEST_CASE("particles: bad values name the full key and show the value", "[particles][scene]") {
  const std::string lattice = "dimension = 2\ncount = 100\nvolume_fraction = 0.2\nboundary = \"periodic\"\n";
  const std::string cloud = lattice + "initial = { cloud = \"cube\" }\n";
  // Radii and masses.
  check_bad(lattice + "radius = 0.0\n", "particles.radius", "0");
  check_bad(lattice + "radius = -1.0\n", "particles.radius", "-1");
  check_bad(cloud + "radius = { distribution = \"normal\", mean = 1.0, sd = -0.1, min = 0.5 }\n", "particles.radius.sd", "-0.1");
  check_bad(cloud + "radius = { distribution = \"normal\", mean = 0.0, sd = 0.1, min = 0.5 }\n", "particles.radius.mean", "0");
  check_bad(cloud + "radius = { distribution = \"normal\", mean = 1.0, sd = 0.1 }\n", "particles.radius.min", "missing");
  check_bad(cloud + "radius = { distribution = \"normal\", mean = 1.0, sd = 0.1, min = -0.5 }\n", "particles.radius.min", "-0.5");
  check_bad(cloud + "radius = { distribution = \"uniform\", min = 2.0, max = 1.0 }\n", "particles.radius.min", "2");
  check_bad(cloud + "radius = { distribution = \"uniform\", min = 1.0, max = 2.0, mean = 1.5 }\n", "particles.radius.mean", "1.5");
  check_bad(cloud + "radius = { distribution = \"weibull\", mean = 1.0, sd = 0.1 }\n", "particles.radius.distribution", "weibull");
  check_bad(cloud + "radius = { distribution = \"normal\", mean = 1.0, sd = 0.1, min = 0.5, shape = 2 }\n", "particles.radius.shape", "2");
  check_bad(cloud + "radius = { distribution = \"lognormal\", mean = 1.0, sd = 0.1, min = 2.0 }\n", "particles.radius.min", "2");
  check_bad(cloud + "radius = 0.5\nmass = { distribution = \"normal\", mean = 1.0, sd = -1.0, min = 0.1 }\n", "particles.mass.sd", "-1");
  check_bad(cloud + "radius = 0.5\nmass = { density = -2.0 }\n", "particles.mass.density", "-2");
  check_bad(cloud + "radius = 0.5\nmass = 0\n", "particles.mass", "0");
  // Starts.
  check_bad(lattice + "radius = { distribution = \"uniform\", min = 0.4, max = 0.6 }\n", "particles.initial.lattice", "square");
  check_bad(lattice + "radius = 0.5\ninitial = { lattice = \"square\", cloud = \"cube\" }\n", "particles.initial.cloud", "cube");
  check_bad(lattice + "radius = 0.5\ninitial = { cloud = \"blob\" }\n", "particles.initial.cloud", "blob");
  check_bad(lattice + "radius = 0.5\ninitial = { cloud = \"cube\", size = 10.0 }\n", "particles.initial.size", "10");
  check_bad(lattice + "radius = 0.5\ninitial = { cloud = \"sphere\" }\n", "particles.initial.size", "missing");
  check_bad(lattice + "radius = 0.5\ninitial = { cloud = \"sphere\", size = 100.0 }\n", "particles.initial.size", "100");
  check_bad(lattice + "radius = 0.5\ninitial = { cloud = \"sphere\", size = 10.0, volume_fraction = 0.2 }\n", "particles.initial.size", "10");
  check_bad(lattice + "radius = 0.5\ninitial = { speed = -1.0 }\n", "particles.initial.speed", "-1");
  // Unreachable volume fractions (random sequential addition jams near 0.547 in 2-D).
  check_bad("dimension = 2\ncount = 400\nvolume_fraction = 0.7\nboundary = \"periodic\"\nradius = 0.5\ninitial = { cloud = \"cube\" }\n",
            "particles.volume_fraction", "0.7");
  check_bad("dimension = 2\ncount = 400\nboundary = \"open\"\nradius = 0.5\ninitial = { cloud = \"sphere\", volume_fraction = 0.7 }\n",
            "particles.initial.volume_fraction", "0.7");
  // Open space.
  const std::string open = "dimension = 3\ncount = 100\nradius = 0.5\nboundary = \"open\"\n";
  check_bad(open + "box = 10.0\ninitial = { cloud = \"cube\", size = 20.0 }\n", "particles.box", "10");
  check_bad(open + "volume_fraction = 0.1\ninitial = { cloud = \"cube\", size = 20.0 }\n", "particles.volume_fraction", "0.1");
  check_bad(open + "initial = { lattice = \"cubic\" }\n", "particles.initial.lattice", "cubic");
  check_bad(open, "particles.initial.lattice", "cubic");  // the default start is a lattice
  check_bad(open + "initial = { cloud = \"cube\" }\n", "particles.initial.size", "missing");
  check_bad("dimension = 2\ncount = 10\nradius = 0.5\nboundary = \"sticky\"\nbox = 10.0\n", "particles.boundary", "sticky");
}

TEST_CASE("particles: bad start files name the file and the line", "[particles][scene]") {
  const auto folder = aggkit::testing::scratch_folder("particles-bad-files");
  const auto file = [&](const std::string& name, const std::string& text) {
    return "dimension = 2\nbox = 10.0\nboundary = \"reflecting\"\ninitial = { file = \"" + write_csv(folder / name, text).string() + "\" }\n";
  };
  const std::string header = "x,y,vx,vy,radius,mass\n";
  const auto check_file = [&](const std::string& particles, const std::string& what) {
    INFO(particles);
    try {
      parse_scene(with_particles(particles));
      FAIL("no InputError");
    } catch (const InputError& e) {
      CHECK(e.key() == "particles.initial.file");
      CHECK_THAT(std::string(e.what()), Contains(folder.string()) && Contains(what));
    }
  };
  check_file(file("columns.csv", header + "1,1,0,0,0.5,1\n3,3,0,0,0.5\n"), "line 3: 5 columns, expected 6");
  check_file(file("number.csv", header + "1,1,0,0,0.5,1\n3,x3,0,0,0.5,1\n"), "line 3: y = \"x3\" is not a number");
  check_file(file("radius.csv", header + "1,1,0,0,-0.5,1\n"), "line 2: radius = -0.5");
  check_file(file("mass.csv", header + "1,1,0,0,0.5,0\n"), "line 2: mass = 0");
  check_file(file("finite.csv", header + "1,1,inf,0,0.5,1\n"), "line 2: vx = inf is not finite");
  check_file(file("header.csv", "x,y,z,vx,vy,vz,radius,mass\n1,1,1,0,0,0,0.5,1\n"), "line 1: the header line must be x,y,vx,vy,radius,mass");
  check_file(file("overlap.csv", header + "1,1,0,0,0.5,1\n5,5,0,0,0.5,1\n1.5,1.2,0,0,0.5,1\n"), "line 4: the particle overlaps the one on line 2");
  check_file(file("outside.csv", header + "1,1,0,0,0.5,1\n9.8,5,0,0,0.5,1\n"), "line 3: position 9.8 along axis x");
  check_file(file("empty.csv", ""), "it is empty");
  check_file("dimension = 2\nbox = 10.0\nboundary = \"reflecting\"\ninitial = { file = \"" + (folder / "missing.csv").string() + "\" }\n",
             "No such file");
  // count, radius, mass and velocity keys against a file.
  const std::string good = file("good.csv", header + "1,1,0,0,0.5,1\n3,3,0,0,0.5,1\n");
  check_bad(good + "count = 3\n", "particles.count", "3");
  check_bad(good + "radius = 0.5\n", "particles.radius", "0.5");
  check_bad(good + "mass = 1.0\n", "particles.mass", "1");
  std::string with_speed = good;
  with_speed.replace(with_speed.find("initial = {"), 11, "initial = { speed = 1.0,");
  check_bad(with_speed, "particles.initial.speed", "1");
}

namespace {

int run_cli(const std::filesystem::path& scene, const std::filesystem::path& folder, std::string& err) {
  const std::string command = std::string("'") + AGGKIT_CLI + "' run '" + scene.string() + "' --out '" +
                              (folder / "out").string() + "' --quiet --no-plot >/dev/null 2>'" +
                              (folder / "stderr.txt").string() + "'";
  const int status = std::system(command.c_str());
  REQUIRE(WIFEXITED(status));
  err = aggkit::testing::read_text(folder / "stderr.txt");
  return WEXITSTATUS(status);
}

}  // namespace

TEST_CASE("particles: bad input through the CLI exits 2 naming the key and value", "[particles][scene][cli]") {
  const auto folder = aggkit::testing::scratch_folder("particles-cli");
  std::string err;
  const auto sd = aggkit::testing::write_text(
      folder / "sd.toml", with_particles("dimension = 2\ncount = 100\nvolume_fraction = 0.2\nboundary = \"periodic\"\n"
                                         "radius = { distribution = \"normal\", mean = 1.0, sd = -0.25, min = 0.5 }\n"
                                         "initial = { cloud = \"cube\" }\n"));
  CHECK(run_cli(sd, folder, err) == 2);
  CHECK_THAT(err, Contains("particles.radius.sd") && Contains("-0.25"));
  // A start file relative to the scene's folder, with a bad row.
  aggkit::testing::write_text(folder / "start.csv", "x,y,vx,vy,radius,mass\n1,1,0,0,0.5,1\n2,2,0,0,0.5\n");
  const auto row = aggkit::testing::write_text(
      folder / "row.toml", with_particles("dimension = 2\nbox = 10.0\nboundary = \"reflecting\"\ninitial = { file = \"start.csv\" }\n"));
  CHECK(run_cli(row, folder, err) == 2);
  CHECK_THAT(err, Contains("particles.initial.file") && Contains((folder / "start.csv").string()) && Contains("line 3"));
  CHECK(aggkit::testing::count_files_named(folder / "out", "summary.json") == 0);
}

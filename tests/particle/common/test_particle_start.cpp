// Starts of a particle system (ParticleSystem::initial_state): today's lattice start bit for bit, the
// independence of the random streams, mass laws, zero momentum, cold starts, clouds, and start files.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "analysis/input_error.hpp"
#include "particle/common/particle_system.hpp"
#include "particle/common/random_packing.hpp"
#include "particle/common/seeds.hpp"

using namespace aggkit;

namespace {

ParticleSystem lattice_system(int d, VelocityLaw law) {
  ParticleSystem s;
  s.box.dimension = d;
  s.box.boundary = Boundary::reflecting;
  s.count = d == 2 ? 100 : 125;
  s.radius_law = PropertyLaw::fixed(0.5);
  const double side = box_side_for_volume_fraction(d, s.count, 0.5, 0.2);
  s.box.side = {side, side, d == 3 ? side : 0.0};
  s.velocities = law;
  s.speed = 1.5;
  s.seed = 7;
  s.realizations = 3;
  return s;
}

PropertyLaw uniform_law(double min, double max) {
  PropertyLaw law;
  law.distribution = Distribution::uniform;
  law.min = min;
  law.max = max;
  return law;
}

// A cloud of spread radii filling a periodic box at ν = 0.2.
ParticleSystem cloud_system(int d) {
  ParticleSystem s;
  s.box.dimension = d;
  s.box.boundary = Boundary::periodic;
  s.count = 300;
  s.radius_law = uniform_law(0.5, 1.0);
  s.start = CloudStart{};
  const double side = std::pow(s.expected_particle_volume() / 0.2, 1.0 / d);
  s.box.side = {side, side, d == 3 ? side : 0.0};
  s.seed = 3;
  return s;
}

double closest_relative_distance(const Box& box, const ParticleStart& s) {
  double closest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i + 1; j < s.size(); ++j)
      closest = std::min(closest, norm(box.minimum_image(s.positions[j] - s.positions[i])) / (s.radii[i] + s.radii[j]));
  return closest;
}

Vector3 momentum(const ParticleStart& s) {
  Vector3 p{0, 0, 0};
  for (std::size_t i = 0; i < s.size(); ++i) p = p + s.masses[i] * s.velocities[i];
  return p;
}

void check_input_error(const ParticleSystem& s, const std::string& key) {
  try {
    s.validate();
    FAIL("no InputError");
  } catch (const InputError& e) {
    CHECK(e.key() == key);
  }
}

}  // namespace

TEST_CASE("the lattice start with a fixed radius is today's start bit for bit", "[particles][start]") {
  for (int d : {2, 3})
    for (const auto law : {VelocityLaw::fixed_speed, VelocityLaw::uniform_components}) {
      const ParticleSystem s = lattice_system(d, law);
      REQUIRE_NOTHROW(s.validate());
      CHECK(s.start_kind() == ParticleSystem::StartKind::lattice);
      CHECK(s.equal_radii());
      CHECK(s.equal_masses());
      CHECK(s.mean_radius() == 0.5);
      CHECK(s.mean_mass() == 1.0);
      CHECK(s.volume_fraction() == volume_fraction(s.box, s.count, 0.5));
      for (std::size_t r = 0; r < s.realizations; ++r) {
        const ParticleStart start = s.initial_state(r);
        const auto expected = initial_velocities(d, s.count, law, 1.5, run_seed(7, r));
        CHECK(start.positions == lattice_positions(s.box, s.count, 0.5));
        CHECK(start.velocities == expected);
        CHECK(start.positions == s.initial_positions());
        CHECK(start.velocities == s.initial_velocities(r));
        CHECK(start.radii == std::vector<double>(s.count, 0.5));
        CHECK(start.masses == std::vector<double>(s.count, 1.0));
      }
      // Random masses draw from their own stream: the velocities stay those of run_seed(seed, r).
      ParticleSystem heavy = s;
      heavy.mass_law.law = uniform_law(1.0, 3.0);
      if (law == VelocityLaw::fixed_speed) CHECK(heavy.initial_state(1).velocities == s.initial_state(1).velocities);
      CHECK(heavy.initial_state(1).positions == s.initial_state(1).positions);
    }
}

TEST_CASE("clouds: no overlaps, fresh per realization, velocities on their own stream", "[particles][start]") {
  for (int d : {2, 3}) {
    const ParticleSystem s = cloud_system(d);
    REQUIRE_NOTHROW(s.validate());
    CHECK(s.start_kind() == ParticleSystem::StartKind::cloud);
    CHECK_FALSE(s.equal_radii());
    CHECK(s.mean_radius() == Approx(0.75).epsilon(1e-12));
    CHECK(s.volume_fraction() == Approx(0.2).epsilon(1e-12));
    CHECK_THROWS_AS(s.initial_positions(), std::logic_error);
    const ParticleStart a = s.initial_state(0), b = s.initial_state(1);
    CHECK(closest_relative_distance(s.box, a) >= 1.0);
    CHECK(closest_relative_distance(s.box, b) >= 1.0);
    CHECK(a.positions != b.positions);
    CHECK(a.radii != b.radii);
    CHECK(s.initial_state(1).positions == b.positions);  // reproducible
    for (double r : a.radii) {
      CHECK(r >= 0.5);
      CHECK(r <= 1.0);
    }
    // Drawing radii and positions never moves the velocity stream.
    CHECK(a.velocities == initial_velocities(d, s.count, VelocityLaw::fixed_speed, 1.0, run_seed(3, 0)));
    CHECK(b.velocities == s.initial_velocities(1));
  }
}

TEST_CASE("clouds: a placement asked again is RSA's own, and a changed box, region, radius or seed places anew", "[particles][start]") {
  // initial_state keeps the last placement of the process and hands it out again for the same (box, region,
  // radii, seed): each answer must be what random_sequential_addition gives for that system, whatever came before.
  const ParticleSystem base = cloud_system(3);
  ParticleSystem other_box = base, fixed_radius = base, sphere = base;
  other_box.box.side[2] *= 1.01;
  fixed_radius.radius_law = PropertyLaw::fixed(0.75);
  ParticleSystem other_seed = fixed_radius;  // the same radii: only the positions' stream differs
  other_seed.seed = 4;
  sphere.start = CloudStart{CloudShape::sphere, std::nullopt, 0.3};
  for (double& side : sphere.box.side) side *= 1.5;  // the sphere holding the particles at ν = 0.3 fits
  for (const ParticleSystem* s : std::vector<const ParticleSystem*>{&base, &fixed_radius, &other_seed, &base, &other_box, &sphere, &base, &base}) {
    const ParticleStart start = s->initial_state(0);
    const Packing direct = random_sequential_addition(s->box, s->cloud_region(), start.radii,
                                                      stream_seed(run_seed(s->seed, 0), StartStream::positions));
    REQUIRE(direct.complete());
    CHECK(start.positions == direct.positions);
  }
  CHECK(fixed_radius.initial_state(0).positions != other_seed.initial_state(0).positions);
  CHECK(base.initial_state(0).positions != other_box.initial_state(0).positions);
}

TEST_CASE("open space: a sphere cloud of a given volume fraction around the origin", "[particles][start]") {
  ParticleSystem s;
  s.box = Box{3, {0, 0, 0}, Boundary::open};
  s.count = 400;
  s.radius_law = PropertyLaw::fixed(1.0);
  s.start = CloudStart{CloudShape::sphere, std::nullopt, 0.15};
  REQUIRE_NOTHROW(s.validate());
  const PackingRegion region = s.cloud_region();
  CHECK(region.centre == Vector3{0, 0, 0});
  CHECK(400 * particle_volume(3, 1.0) / region.volume(3) == Approx(0.15).epsilon(1e-12));
  CHECK(s.volume_fraction() == 0.15);
  const ParticleStart start = s.initial_state(0);
  for (std::size_t i = 0; i < s.count; ++i) CHECK(norm(start.positions[i]) <= region.size / 2 - 1.0 + 1e-12);
  CHECK(closest_relative_distance(s.box, start) >= 1.0);
  // A lattice needs a box.
  ParticleSystem lattice = s;
  lattice.start = LatticeStart{};
  check_input_error(lattice, "initial.lattice");
}

TEST_CASE("a cloud denser than RSA can place is an InputError naming the fraction", "[particles][start]") {
  ParticleSystem s = cloud_system(2);
  s.radius_law = PropertyLaw::fixed(0.5);
  s.count = 500;
  const double side = std::sqrt(500 * particle_volume(2, 0.5) / 0.7);
  s.box.side = {side, side, 0};
  check_input_error(s, "volume_fraction");
  ParticleSystem open;
  open.box = Box{2, {0, 0, 0}, Boundary::open};
  open.count = 500;
  open.radius_law = PropertyLaw::fixed(0.5);
  open.start = CloudStart{CloudShape::cube, std::nullopt, 0.7};
  try {
    open.validate();
    FAIL("no InputError");
  } catch (const InputError& e) {
    CHECK(e.key() == "initial.volume_fraction");
    CHECK_THAT(e.what(), Catch::Contains("0.7") && Catch::Contains("0.547"));
  }
}

TEST_CASE("a density mass law gives m = 4/3 pi rho R^3 (pi rho R^2 in 2-D)", "[particles][start]") {
  for (int d : {2, 3}) {
    ParticleSystem s = cloud_system(d);
    s.mass_law.density = 2.5;
    REQUIRE_NOTHROW(s.validate());
    CHECK_FALSE(s.equal_masses());
    const ParticleStart start = s.initial_state(0);
    for (std::size_t i = 0; i < s.count; ++i) {
      const double r = start.radii[i];
      CHECK(start.masses[i] == 2.5 * particle_volume(d, r));
      CHECK(start.masses[i] == Approx(d == 3 ? 4.0 / 3 * std::numbers::pi * 2.5 * r * r * r
                                             : std::numbers::pi * 2.5 * r * r).epsilon(1e-15));
    }
    CHECK(s.mean_mass() == Approx(2.5 * s.expected_particle_volume() / double(s.count)).epsilon(1e-14));
  }
}

TEST_CASE("uniform components have zero momentum with unequal masses, speed 0 is a cold start", "[particles][start]") {
  for (int d : {2, 3}) {
    ParticleSystem s = cloud_system(d);
    s.mass_law.density = 3.0;
    s.velocities = VelocityLaw::uniform_components;
    const ParticleStart start = s.initial_state(2);
    const Vector3 p = momentum(start);
    CHECK(norm(p) < 1e-12);
    CHECK(start.velocities == s.initial_velocities(2));
    double speed_sum = 0;
    for (const auto& v : start.velocities) speed_sum += norm(v);
    CHECK(speed_sum > 0.1 * double(s.count));  // not trivially zero
    s.speed = 0;
    REQUIRE_NOTHROW(s.validate());
    CHECK(s.cold());
    for (const auto& v : s.initial_state(0).velocities) CHECK(v == Vector3{0, 0, 0});
  }
  ParticleSystem negative = lattice_system(2, VelocityLaw::fixed_speed);
  negative.speed = -1;
  check_input_error(negative, "initial.speed");
}

TEST_CASE("a start file round-trips a written start", "[particles][start]") {
  const auto folder = std::filesystem::path(AGGKIT_TEST_TMP) / "particle-start-file";
  std::filesystem::create_directories(folder);
  for (int d : {2, 3}) {
    ParticleSystem cloud = cloud_system(d);
    cloud.mass_law.law = uniform_law(1, 2);
    cloud.velocities = VelocityLaw::uniform_components;
    const ParticleStart written = cloud.initial_state(0);
    const auto path = folder / ("start-" + std::to_string(d) + "d.csv");
    write_start_file(path, d, written);
    ParticleSystem s = cloud;
    s.start = FileStart{read_start_file(path, d)};
    REQUIRE_NOTHROW(s.validate());
    CHECK(s.start_kind() == ParticleSystem::StartKind::file);
    const ParticleStart read = s.initial_state(5);
    CHECK(read.positions == written.positions);
    CHECK(read.velocities == written.velocities);
    CHECK(read.radii == written.radii);
    CHECK(read.masses == written.masses);
    CHECK(s.initial_positions() == written.positions);
    CHECK(s.mean_radius() == Approx(cloud.mean_radius()).epsilon(0.05));
    CHECK(std::get<FileStart>(s.start).file.lines.front() == 2);
    // The file's count and box are checked.
    s.count += 1;
    check_input_error(s, "count");
    s.count -= 1;
    s.box.side = {s.box.side[0] / 2, s.box.side[1] / 2, s.box.side[2] / 2};
    check_input_error(s, "initial.file");
  }
}

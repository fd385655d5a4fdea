// [particles]: the particle system of the particle engines (particle/common/particle_system.hpp).
//   dimension = 2                       2 or 3 (required)
//   count = 400                         N >= 2 (required)
//   radius = 0.2                        R > 0 (required)
//   volume_fraction = 0.1               ν in (0, 1): square/cubic box of side (N v_1 / ν)^{1/d}; or
//   box = 20.0  or  [20.0, 10.0]        the box sides
//   boundary = "reflecting"             periodic | reflecting (required)
//   initial = { lattice = "square", speed = 1.0, directions = "uniform" }
//          or { lattice = "square", speed = 1.0, components = "uniform" }   (zero total momentum)
//                                       lattice square (2-D) | cubic (3-D); speed default 1
//   thermalize = 10                     elastic collisions per particle before sticking (default 0)
//   seed = 1                            (default 1)
//   realizations = 10                   independent runs (different velocities), default 1
#include "validation/scene/scene_sections.hpp"

namespace aggkit {

namespace {

void read_box(const SceneTable& particles, ParticleSystem& system) {
  const bool by_fraction = particles.contains("volume_fraction"), by_box = particles.contains("box");
  if (by_fraction == by_box) particles.fail(by_box ? "box" : "volume_fraction", "exactly one of volume_fraction and box");
  const int d = system.box.dimension;
  if (by_fraction) {
    const double nu = particles.number("volume_fraction", Bound::positive);
    if (!(nu < 1)) particles.fail("volume_fraction", "a volume fraction in (0, 1)");
    const double side = box_side_for_volume_fraction(d, system.count, system.radius, nu);
    system.box.side = {side, side, d == 3 ? side : 0.0};
    return;
  }
  const toml::node* node = particles.find("box");
  if (node->is_array()) {
    const std::vector<double> sides = particles.numbers("box", Bound::positive);
    if (int(sides.size()) != d) particles.fail("box", "one side per dimension (" + std::to_string(d) + ")");
    for (int a = 0; a < d; ++a) system.box.side[a] = sides[a];
  } else {
    const double side = particles.number("box", Bound::positive);
    system.box.side = {side, side, d == 3 ? side : 0.0};
  }
}

void read_initial(const SceneTable& particles, ParticleSystem& system) {
  const auto initial = particles.optional_table("initial");
  if (!initial) return;  // lattice, unit speed, uniform directions
  initial->allow_only({"lattice", "speed", "directions", "components"});
  if (const auto lattice = initial->optional_string("lattice"))
    if (*lattice != (system.box.dimension == 2 ? "square" : "cubic"))
      initial->fail("lattice", system.box.dimension == 2 ? "\"square\" (2-D)" : "\"cubic\" (3-D)");
  system.speed = initial->optional_number("speed", Bound::positive).value_or(1.0);
  const bool directions = initial->contains("directions"), components = initial->contains("components");
  if (directions && components) initial->fail("components", "either directions = \"uniform\" or components = \"uniform\"");
  if (directions && initial->string("directions") != "uniform") initial->fail("directions", "\"uniform\"");
  if (components && initial->string("components") != "uniform") initial->fail("components", "\"uniform\"");
  system.velocities = components ? VelocityLaw::uniform_components : VelocityLaw::fixed_speed;
}

}  // namespace

ParticleSystem read_particles(const SceneTable& particles) {
  particles.allow_only({"dimension", "count", "radius", "volume_fraction", "box", "boundary", "initial", "thermalize",
                        "seed", "realizations"});
  ParticleSystem system;
  const std::size_t dimension = particles.count("dimension", 2);
  if (dimension != 2 && dimension != 3) particles.fail("dimension", "2 or 3");
  system.box.dimension = int(dimension);
  system.count = particles.count("count", 2);
  system.radius = particles.number("radius", Bound::positive);
  read_box(particles, system);
  system.box.boundary = under_key([&](const std::string&) { return particles.key("boundary"); },
                                  [&] { return boundary_from_name(particles.string("boundary")); });
  read_initial(particles, system);
  system.thermalize = particles.optional_count("thermalize", 0).value_or(0);
  system.seed = particles.optional_count("seed", 0).value_or(1);
  system.realizations = particles.optional_count("realizations", 1).value_or(1);
  system.validate();
  return system;
}

}  // namespace aggkit

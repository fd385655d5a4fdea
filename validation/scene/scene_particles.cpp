// [particles]: the particle system of the particle engines (particle/common/particle_system.hpp).
//   dimension = 2                       2 or 3 (required)
//   count = 400                         N >= 2 (required; with a file start optional, and then equal to the
//                                       number of particles in the file)
//   radius = 0.2                        R > 0 (required, except with a file start, where it is an error);
//          or { distribution = "normal", mean = 1.0, sd = 0.1, min = 0.5, max = 2.0 }
//                                       per-particle radii drawn for each realization: normal truncated to
//                                       [min, max] (min > 0 required, max default inf); lognormal with the
//                                       mean and sd of R itself (not of ln R), min (default 0) and max optional;
//          or { distribution = "uniform", min = 0.5, max = 1.5 }    (mean and sd not allowed)
//                                       the truncation window must hold at least 1e-3 of the law
//   mass = 1.0                          m > 0 per particle (default 1); or a distribution table as for radius;
//          or { density = 2.5 }         m = ρ·4πR³/3 (3-D) or ρ·πR² (2-D) per particle
//                                       (an error with a file start: the file gives the masses)
//   volume_fraction = 0.1               ν in (0, 1): square/cubic box of side (Σ v_i / ν)^{1/d}, Σ v_i the
//                                       expected total particle volume (N·E[v(R)] for a radius distribution,
//                                       the file's sum for a file start); or
//   box = 20.0  or  [20.0, 10.0]        the box sides; exactly one of the two, and neither with "open"
//   boundary = "reflecting"             periodic | reflecting | open (required; open: no box, particles in
//                                       unbounded space, and the start must be a cloud or a file)
//   initial = { lattice = "square", speed = 1.0, directions = "uniform" }
//          or { lattice = "square", speed = 1.0, components = "uniform" }   (zero total momentum)
//                                       lattice square (2-D) | cubic (3-D), filling the box; equal radii only.
//                                       The default start (no initial table) is this lattice with speed 1.
//          or { cloud = "cube", speed = 1.0, directions = "uniform" }
//          or { cloud = "sphere", size = 10.0 | volume_fraction = 0.2, speed = ..., components = "uniform" }
//                                       uniformly random positions without overlaps (random sequential addition,
//                                       larger particles first), drawn for each realization. Open boundary: a
//                                       cube of side `size` (sphere of diameter `size`) centred at the origin, or
//                                       sized so that Σ v_i / region volume = volume_fraction (exactly one of the
//                                       two). In a box: cloud = "cube" fills the box (size and volume_fraction
//                                       are then errors: the box decides), cloud = "sphere" is centred in the
//                                       box with diameter `size` or from volume_fraction, and must fit in it.
//                                       RSA jams near ν = 0.547 (2-D) and 0.38 (3-D): denser clouds are errors.
//          or { file = "start.csv" }    every particle from a CSV file with a header line, columns
//                                       x,y,vx,vy,radius,mass (2-D) or x,y,z,vx,vy,vz,radius,mass (3-D); the path
//                                       is relative to the scene file's folder (the current folder for a scene
//                                       given as text); particles must lie inside the box and not overlap
//                                       (speed, directions and components are errors: the file gives velocities)
//                                       speed >= 0, default 1 (0: a cold start, every velocity zero); velocities
//                                       of fixed speed in uniformly random directions (directions = "uniform",
//                                       the default) or with independent uniform components in [-speed, speed],
//                                       total momentum removed (components = "uniform")
//   thermalize = 10                     elastic collisions per particle before sticking (an ED setting)
//   seed = 7                            realization r runs on the seed mixed with r
//   realizations = 10                   independent runs (different velocities, and radii, masses and cloud
//                                       positions where those are random)
//                                       (these three: option rows with their ranges and defaults,
//                                       particle/common/particle_system_options.cpp)
#include <cmath>
#include <limits>

#include "validation/io/machine.hpp"
#include "validation/scene/scene_sections.hpp"

namespace aggkit {

namespace {

// Runs library code whose InputError keys are relative to the section, re-throwing them under "particles.".
template <class F>
auto in_section(const SceneTable& particles, F&& f) -> decltype(f()) {
  return under_key([&](const std::string& key) { return particles.key(key); }, std::forward<F>(f));
}

// A radius or mass law: a number, or a distribution table. The values are checked by PropertyLaw::validate.
PropertyLaw read_law(const SceneTable& section, const std::string& name) {
  const toml::node* node = section.find(name);
  if (!node || !node->is_table()) return PropertyLaw::fixed(section.number(name, Bound::any));
  const SceneTable table = section.table(name);
  table.allow_only({"distribution", "mean", "sd", "min", "max"});
  PropertyLaw law;
  const std::string kind = table.string("distribution");
  law.distribution = under_key([&](const std::string&) { return table.key("distribution"); },
                               [&] { return distribution_from_name(kind); });
  if (law.distribution == Distribution::uniform) {
    for (const char* key : {"mean", "sd"})
      if (table.contains(key)) table.fail(key, "not with distribution = \"uniform\" (give min and max only)");
    law.min = table.number("min", Bound::any);
    law.max = table.number("max", Bound::any);
    return law;
  }
  law.mean = table.number("mean", Bound::any);
  law.sd = table.number("sd", Bound::any);
  if (law.distribution == Distribution::normal)
    law.min = table.number("min", Bound::any);  // required: a normal law reaches negative values
  else
    law.min = table.optional_number("min", Bound::any).value_or(0.0);
  law.max = table.optional_number("max", Bound::any).value_or(std::numeric_limits<double>::infinity());
  return law;
}

MassLaw read_mass(const SceneTable& particles) {
  MassLaw mass;
  const toml::node* node = particles.find("mass");
  if (!node) return mass;  // 1 for every particle
  if (node->is_table() && node->as_table()->contains("density")) {
    const SceneTable table = particles.table("mass");
    table.allow_only({"density"});
    mass.density = table.number("density", Bound::any);
    return mass;
  }
  mass.law = read_law(particles, "mass");
  return mass;
}

// The velocity law of a lattice or cloud start.
void read_velocities(const SceneTable& initial, ParticleSystem& system) {
  system.speed = initial.optional_number("speed", Bound::non_negative).value_or(1.0);
  const bool directions = initial.contains("directions"), components = initial.contains("components");
  if (directions && components) initial.fail("components", "either directions = \"uniform\" or components = \"uniform\"");
  if (directions && initial.string("directions") != "uniform") initial.fail("directions", "\"uniform\"");
  if (components && initial.string("components") != "uniform") initial.fail("components", "\"uniform\"");
  system.velocities = components ? VelocityLaw::uniform_components : VelocityLaw::fixed_speed;
}

std::filesystem::path resolved(const std::filesystem::path& file, const std::filesystem::path& folder) {
  return file.is_absolute() || folder.empty() ? file : folder / file;
}

void read_initial(const SceneTable& particles, ParticleSystem& system, const std::filesystem::path& folder) {
  const auto initial = particles.optional_table("initial");
  if (!initial) return;  // lattice, unit speed, uniform directions
  const char* forms[] = {"lattice", "cloud", "file"};
  const char* form = nullptr;
  for (const char* f : forms)
    if (initial->contains(f)) {
      if (form) initial->fail(f, std::string("one start: lattice, cloud or file, not both ") + form + " and " + f);
      form = f;
    }
  const std::string which = form ? form : "lattice";
  if (which == "file") {
    for (const char* key : {"speed", "directions", "components"})
      if (initial->contains(key)) initial->fail(key, "not with a file start: the file gives the velocities (vx, vy[, vz])");
    initial->allow_only({"file"});
    const std::filesystem::path path = resolved(initial->string("file"), folder);
    system.start = FileStart{in_section(particles, [&] { return read_start_file(path, system.box.dimension); })};
    return;
  }
  if (which == "cloud") {
    initial->allow_only({"cloud", "size", "volume_fraction", "speed", "directions", "components"});
    CloudStart cloud;
    const std::string shape = initial->string("cloud");
    if (shape != "cube" && shape != "sphere") initial->fail("cloud", "\"cube\" or \"sphere\"");
    cloud.shape = shape == "cube" ? CloudShape::cube : CloudShape::sphere;
    cloud.size = initial->optional_number("size", Bound::positive);
    cloud.volume_fraction = initial->optional_number("volume_fraction", Bound::positive);
    system.start = cloud;
    read_velocities(*initial, system);
    return;
  }
  initial->allow_only({"lattice", "speed", "directions", "components"});
  if (const auto lattice = initial->optional_string("lattice"))
    if (*lattice != (system.box.dimension == 2 ? "square" : "cubic"))
      initial->fail("lattice", system.box.dimension == 2 ? "\"square\" (2-D)" : "\"cubic\" (3-D)");
  system.start = LatticeStart{};
  read_velocities(*initial, system);
}

void read_box(const SceneTable& particles, ParticleSystem& system) {
  const bool by_fraction = particles.contains("volume_fraction"), by_box = particles.contains("box");
  if (system.box.boundary == Boundary::open) {
    if (by_fraction || by_box)
      particles.fail(by_box ? "box" : "volume_fraction",
                     "no box with boundary = \"open\" (the particles are in unbounded space; size a cloud start "
                     "with initial.size or initial.volume_fraction)");
    system.box.side = {0, 0, 0};
    return;
  }
  if (by_fraction == by_box) particles.fail(by_box ? "box" : "volume_fraction", "exactly one of volume_fraction and box");
  const int d = system.box.dimension;
  if (by_fraction) {
    const double nu = particles.number("volume_fraction", Bound::positive);
    if (!(nu < 1)) particles.fail("volume_fraction", "a volume fraction in (0, 1)");
    // A fixed radius keeps the side formula of box.hpp bit for bit; otherwise the expected total volume.
    const bool fixed = system.start_kind() != ParticleSystem::StartKind::file && system.radius_law.is_fixed();
    const double side = fixed ? box_side_for_volume_fraction(d, system.count, system.radius_law.value, nu)
                              : std::pow(in_section(particles, [&] { return system.expected_particle_volume(); }) / nu, 1.0 / d);
    if (!std::isfinite(side) || !(side > 0))  // e.g. radius = 1e300: the side overflows
      particles.fail("radius", "a radius whose box at volume_fraction = " + shortest_text(nu) + " is a finite length "
                               "(here the side (N v / nu)^(1/d) is " + shortest_text(side) + ")");
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

}  // namespace

ParticleSystem read_particles(const SceneTable& particles, const std::filesystem::path& folder) {
  particles.allow_only({"dimension", "count", "radius", "mass", "volume_fraction", "box", "boundary", "initial",
                        "thermalize", "seed", "realizations"});
  ParticleSystem system;
  const std::size_t dimension = particles.count("dimension", 2);
  if (dimension != 2 && dimension != 3) particles.fail("dimension", "2 or 3");
  system.box.dimension = int(dimension);
  system.box.boundary = under_key([&](const std::string&) { return particles.key("boundary"); },
                                  [&] { return boundary_from_name(particles.string("boundary")); });
  read_initial(particles, system, folder);
  if (system.start_kind() == ParticleSystem::StartKind::file) {
    for (const char* key : {"radius", "mass"})
      if (particles.contains(key))
        particles.fail(key, std::string("not with a file start: the file gives every particle's ") + key);
    const std::size_t rows = std::get<FileStart>(system.start).file.particles.size();
    system.count = particles.optional_count("count", 2).value_or(rows);
  } else {
    system.count = particles.count("count", 2);
    // The start itself (positions, velocities, radii, masses: 64 bytes a particle, with working copies) is
    // made to check it: refuse a count this machine cannot hold before allocating.
    check_memory(particles.key("count"), std::to_string(system.count), 200.0 * double(system.count),
                 "the particles' start: about 200 bytes per particle");
    // Range checks of the laws (and of every other value) are ParticleSystem::validate's.
    system.radius_law = read_law(particles, "radius");
    in_section(particles, [&] { system.radius_law.validate("radius"); });
    system.mass_law = read_mass(particles);
  }
  read_box(particles, system);
  particles.read_rows(particle_system_option_rows(), system);
  in_section(particles, [&] { system.validate(); });
  return system;
}

}  // namespace aggkit

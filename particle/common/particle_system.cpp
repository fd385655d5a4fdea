// The description of a particle system: means, volume fraction, the cloud region, validation and the
// one-line summary (the per-realization starts are in particle_system_start.cpp).
#include "particle/common/particle_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "analysis/input_error.hpp"

namespace aggkit {

namespace {

const StartFile* file_of(const ParticleSystem& system) {
  const FileStart* start = std::get_if<FileStart>(&system.start);
  return start ? &start->file : nullptr;
}

bool all_equal(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [&](double x) { return x == values.front(); });
}

double mean_of(const std::vector<double>& values) {
  double sum = 0;
  for (double x : values) sum += x;
  return sum / double(values.size());
}

// Diameter of the disc (2-D) or sphere (3-D) of the given area/volume: πD²/4 or πD³/6.
double sphere_diameter(int dimension, double volume) {
  return dimension == 2 ? std::sqrt(4 * volume / std::numbers::pi) : std::cbrt(6 * volume / std::numbers::pi);
}

std::string quoted(const std::filesystem::path& path) {
  std::string text = "\"";
  text += path.string();
  return text += "\"";
}

std::string lattice_name(int dimension) { return dimension == 2 ? "\"square\"" : "\"cubic\""; }

}  // namespace

bool ParticleSystem::equal_radii() const {
  if (const StartFile* file = file_of(*this)) return all_equal(file->particles.radii);
  return radius_law.is_fixed();
}

double ParticleSystem::mean_radius() const {
  if (const StartFile* file = file_of(*this)) return mean_of(file->particles.radii);
  return radius_law.expected_value();
}

double ParticleSystem::largest_radius() const {
  if (const StartFile* file = file_of(*this))
    return *std::max_element(file->particles.radii.begin(), file->particles.radii.end());
  return radius_law.largest();
}

bool ParticleSystem::equal_masses() const {
  if (const StartFile* file = file_of(*this)) return all_equal(file->particles.masses);
  return mass_law.density ? radius_law.is_fixed() : mass_law.law.is_fixed();
}

double ParticleSystem::mean_mass() const {
  if (const StartFile* file = file_of(*this)) return mean_of(file->particles.masses);
  if (mass_law.density) return *mass_law.density * expected_particle_volume() / double(count);
  return mass_law.law.expected_value();
}

bool ParticleSystem::cold() const {
  if (const StartFile* file = file_of(*this))
    return std::all_of(file->particles.velocities.begin(), file->particles.velocities.end(),
                       [](const Vector3& v) { return v[0] == 0 && v[1] == 0 && v[2] == 0; });
  return speed == 0;
}

double ParticleSystem::expected_particle_volume() const {
  const int d = box.dimension;
  if (const StartFile* file = file_of(*this)) {
    double sum = 0;
    for (double r : file->particles.radii) sum += particle_volume(d, r);
    return sum;
  }
  if (radius_law.is_fixed()) return double(count) * particle_volume(d, radius_law.value);
  return double(count) * radius_law.expectation([d](double r) { return particle_volume(d, r); });
}

double ParticleSystem::volume_fraction() const {
  if (box.boundary == Boundary::open) {
    if (start_kind() != StartKind::cloud) return std::numeric_limits<double>::quiet_NaN();
    const CloudStart& cloud = std::get<CloudStart>(start);
    if (cloud.volume_fraction) return *cloud.volume_fraction;
    return expected_particle_volume() / cloud_region().volume(box.dimension);
  }
  if (start_kind() != StartKind::file && radius_law.is_fixed())
    return aggkit::volume_fraction(box, count, radius_law.value);  // N v_1 / V, as for every fixed radius
  return expected_particle_volume() / box.volume();
}

PackingRegion ParticleSystem::cloud_region() const {
  const CloudStart* cloud = std::get_if<CloudStart>(&start);
  if (!cloud) throw std::logic_error("ParticleSystem::cloud_region: not a cloud start");
  PackingRegion region;
  const int d = box.dimension;
  const bool open = box.boundary == Boundary::open;
  if (!open && cloud->shape == CloudShape::cube) return region;  // the whole box
  region.shape = cloud->shape == CloudShape::cube ? PackingRegion::Shape::cube : PackingRegion::Shape::sphere;
  if (!open)
    for (int a = 0; a < d; ++a) region.centre[a] = box.side[a] / 2;
  if (cloud->size) {
    region.size = *cloud->size;
  } else if (cloud->volume_fraction) {
    const double volume = expected_particle_volume() / *cloud->volume_fraction;
    region.size = cloud->shape == CloudShape::cube ? std::pow(volume, 1.0 / d) : sphere_diameter(d, volume);
  }
  return region;
}

namespace {

// The size of a cloud start: either size or volume fraction, or neither for a cube filling its box; in a
// box, a sphere that fits.
void validate_cloud(const ParticleSystem& system, const CloudStart& cloud) {
  const bool open = system.box.boundary == Boundary::open;
  if (cloud.size && (!(*cloud.size > 0) || !std::isfinite(*cloud.size)))
    throw InputError("initial.size", format_value(*cloud.size), "a finite size > 0 (cube side or sphere diameter)");
  if (cloud.volume_fraction && (!(*cloud.volume_fraction > 0) || !(*cloud.volume_fraction < 1)))
    throw InputError("initial.volume_fraction", format_value(*cloud.volume_fraction), "a volume fraction in (0, 1)");
  if (!open && cloud.shape == CloudShape::cube) {
    const char* given = cloud.size ? "initial.size" : cloud.volume_fraction ? "initial.volume_fraction" : nullptr;
    if (given)
      throw InputError(given, format_value(cloud.size ? *cloud.size : *cloud.volume_fraction),
                       "no size or volume fraction for cloud = \"cube\" in a box: the cloud fills the box, whose "
                       "size comes from volume_fraction or box");
    return;
  }
  if (cloud.size && cloud.volume_fraction)
    throw InputError("initial.size", format_value(*cloud.size), "either size or volume_fraction, not both");
  if (!cloud.size && !cloud.volume_fraction)
    throw InputError("initial.size", "(missing)",
                     std::string("required: the size (") + (cloud.shape == CloudShape::cube ? "side" : "diameter") +
                         ") or volume_fraction of the cloud" + (open ? " in open space" : " sphere"));
  if (open) return;
  const double diameter = system.cloud_region().size;
  double shortest = system.box.side[0];
  for (int a = 1; a < system.box.dimension; ++a) shortest = std::min(shortest, system.box.side[a]);
  if (diameter > shortest)
    throw InputError(cloud.size ? "initial.size" : "initial.volume_fraction",
                     format_value(cloud.size ? *cloud.size : *cloud.volume_fraction),
                     "a sphere that fits in the box: its diameter " + format_value(diameter) +
                         " exceeds the shortest box side " + format_value(shortest));
}

// A file start: inside the box (walls: at least its radius from each) and without overlaps.
void validate_file_start(const Box& box, const StartFile& file) {
  const ParticleStart& p = file.particles;
  const std::string shown = quoted(file.path);
  if (box.boundary != Boundary::open)
    for (std::size_t i = 0; i < p.size(); ++i)
      for (int a = 0; a < box.dimension; ++a) {
        const double x = p.positions[i][a], r = p.radii[i], side = box.side[a];
        const bool periodic = box.boundary == Boundary::periodic;
        if (periodic ? (x < 0 || x >= side) : (x < r || x > side - r))
          throw InputError("initial.file", shown,
                           file.where(i) + ": position " + format_value(x) + " along axis " + "xyz"[a] +
                               (periodic ? " outside the periodic box [0, " + format_value(side) + ")"
                                         : " puts the particle (radius " + format_value(r) +
                                               ") outside the walls: R <= x <= L - R with L = " + format_value(side)));
      }
  if (const auto pair = first_overlap(box, p.positions, p.radii)) {
    const auto [i, j] = *pair;
    const double distance = norm(box.minimum_image(p.positions[j] - p.positions[i]));
    throw InputError("initial.file", shown,
                     file.where(j) + ": the particle overlaps the one on line " + std::to_string(file.lines[i]) +
                         " (centre distance " + format_value(distance) + " < R_i + R_j = " +
                         format_value(p.radii[i] + p.radii[j]) + ")");
  }
}

// The laws of radius and mass, or (a file start) the count the file gives.
void validate_laws(const ParticleSystem& system, const StartFile* file) {
  if (file) {
    if (file->particles.size() != system.count)
      throw InputError("count", std::to_string(system.count),
                       "the number of particles in initial.file (" + std::to_string(file->particles.size()) + " in " +
                           file->path.string() + "), or no count");
    return;
  }
  system.radius_law.validate("radius");
  if (!system.mass_law.density) return system.mass_law.law.validate("mass");
  if (!(*system.mass_law.density > 0) || !std::isfinite(*system.mass_law.density))
    throw InputError("mass.density", format_value(*system.mass_law.density), "a finite density > 0");
}

}  // namespace

void ParticleSystem::validate() const {
  box.validate();
  const int d = box.dimension;
  const bool open = box.boundary == Boundary::open;
  if (count < 2) throw InputError("count", std::to_string(count), "an integer >= 2");
  if (count >= 0xffffffffu) throw InputError("count", std::to_string(count), "fewer than 2^32 - 1 particles");
  if (!(speed >= 0) || !std::isfinite(speed))
    throw InputError("initial.speed", format_value(speed), "a finite speed >= 0 (0: a cold start, every velocity zero)");
  particle_system_option_rows().check(*this);
  const StartFile* file = file_of(*this);
  validate_laws(*this, file);

  if (start_kind() == StartKind::lattice) {
    if (open)
      throw InputError("initial.lattice", lattice_name(d),
                       "a cloud or file start with boundary = \"open\" (a lattice fills a box): initial = { cloud = "
                       "\"cube\" | \"sphere\", ... } or { file = \"...\" }");
    if (!radius_law.is_fixed())
      throw InputError("initial.lattice", lattice_name(d),
                       "equal radii (radius a number); with a radius distribution use initial = { cloud = ... }");
  }

  if (box.boundary == Boundary::periodic) {
    // Today's rule for a fixed radius R; with unequal radii the largest one (the mean for an unbounded law).
    const double reach = std::isfinite(largest_radius()) ? largest_radius() : mean_radius();
    for (int a = 0; a < d; ++a)
      if (box.side[a] < 6 * reach)
        throw InputError("box", format_value(box.side[a]),
                         std::string("periodic box sides of at least 6R = ") + format_value(6 * reach) +
                             (equal_radii() ? "" : " (R the largest radius)"));
  }

  switch (start_kind()) {
    case StartKind::lattice:
      try {
        (void)lattice_positions(box, count, radius_law.value);
      } catch (const InputError&) {
        throw InputError("volume_fraction", format_value(volume_fraction()),
                         "a volume fraction at which the " + std::to_string(count) +
                             " particles fit on the square/cubic lattice without overlapping (about pi/4 in 2-D, pi/6 in 3-D at most)");
      }
      break;
    case StartKind::cloud:
      validate_cloud(*this, std::get<CloudStart>(start));
      // The placement can only be tried: place realization 0 once (O(N) expected).
      (void)initial_state(0);
      break;
    case StartKind::file:
      validate_file_start(box, *file);
      break;
  }
}

std::string ParticleSystem::describe() const {
  std::ostringstream out;
  out << count << " particles, " << box.dimension << "-D, ";
  const StartFile* file = file_of(*this);
  if (file) {
    out << "from " << file->path.string() << ", mean R = " << mean_radius();
  } else {
    out << "R = ";
    if (radius_law.is_fixed()) out << radius_law.value;
    else out << radius_law.describe();
    if (mass_law.density) out << ", density " << *mass_law.density;
    else if (!mass_law.law.is_fixed() || mass_law.law.value != 1.0) out << ", m = " << mass_law.law.describe();
  }
  if (box.boundary != Boundary::open || start_kind() == StartKind::cloud) out << ", volume fraction " << volume_fraction();
  out << ", " << to_string(box.boundary);
  if (const CloudStart* cloud = std::get_if<CloudStart>(&start)) {
    const PackingRegion region = cloud_region();
    out << ", random " << (cloud->shape == CloudShape::cube ? "cube" : "sphere") << " start";
    if (region.shape != PackingRegion::Shape::whole_box)
      out << " (" << (cloud->shape == CloudShape::cube ? "side " : "diameter ") << region.size << ")";
  }
  if (!file) {
    if (cold()) out << ", cold start";
    else out << ", " << (velocities == VelocityLaw::fixed_speed ? "speed " : "uniform components ±") << speed;
  }
  if (thermalize > 0) out << ", thermalised (" << thermalize << " collisions each)";
  if (realizations > 1) out << ", " << realizations << " realizations";
  return out.str();
}

}  // namespace aggkit

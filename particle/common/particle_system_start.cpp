// One realization's start of a particle system: radii, masses, positions and velocities, each from its
// own random stream (seeds.hpp).
#include <algorithm>
#include <functional>
#include <limits>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "analysis/input_error.hpp"
#include "particle/common/particle_system.hpp"
#include "particle/common/seeds.hpp"

namespace aggkit {

namespace {

const StartFile* file_of(const ParticleSystem& system) {
  const FileStart* start = std::get_if<FileStart>(&system.start);
  return start ? &start->file : nullptr;
}

std::vector<double> radii_of(const ParticleSystem& system, std::uint64_t run) {
  return system.radius_law.draw(system.count, stream_seed(run, StartStream::radii));
}

std::vector<double> masses_of(const ParticleSystem& system, std::uint64_t run, const std::vector<double>& radii) {
  if (!system.mass_law.density) return system.mass_law.law.draw(system.count, stream_seed(run, StartStream::masses));
  std::vector<double> masses(radii.size());
  for (std::size_t i = 0; i < radii.size(); ++i) masses[i] = *system.mass_law.density * particle_volume(system.box.dimension, radii[i]);
  return masses;
}

bool all_equal(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [&](double x) { return x == values.front(); });
}

// Velocities of realization `run`: the stream of the first starts (run_seed itself), zero for a cold start.
// Uniform components with unequal masses: aggkit::initial_velocities removes the plain mean velocity; the
// mass-weighted mean is removed as well so that Σ m_i v_i = 0 (with equal masses it is zero already and the
// velocities are left bit for bit as they were).
std::vector<Vector3> velocities_of(const ParticleSystem& system, std::uint64_t run, const std::vector<double>& masses) {
  const int d = system.box.dimension;
  if (system.speed == 0) return std::vector<Vector3>(system.count, Vector3{0, 0, 0});
  std::vector<Vector3> v = initial_velocities(d, system.count, system.velocities, system.speed, run);
  if (system.velocities == VelocityLaw::uniform_components && !all_equal(masses)) {
    Vector3 momentum{0, 0, 0};
    double mass = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
      momentum = momentum + masses[i] * v[i];
      mass += masses[i];
    }
    const Vector3 centre_of_mass_velocity = (1.0 / mass) * momentum;
    for (auto& u : v) u = u - centre_of_mass_velocity;
  }
  return v;
}

// The last cloud placement of this process, handed out again when the same one is asked for: RSA is a
// function of (box, region, radii, seed) alone, so the copy is the placement it would make. Before a run
// starts the same particles are otherwise placed many times over: the scene check places realization 0
// (particle_system.cpp), DEM calibrates its time step on realization 0, and a sweep plan reads and builds
// the scene of every swept value and of its first points (each placing realization 0 again). One entry: the
// memory is one start's positions and radii.
Packing placement(const Box& box, const PackingRegion& region, const std::vector<double>& radii, std::uint64_t seed) {
  struct Last {
    Box box;
    PackingRegion region;
    std::vector<double> radii;
    std::uint64_t seed = 0;
    Packing packing;
  };
  static std::mutex mutex;
  static Last last;
  static bool held = false;
  const auto same = [&] {
    return held && last.seed == seed && last.box.dimension == box.dimension && last.box.side == box.side &&
           last.box.boundary == box.boundary && last.region.shape == region.shape && last.region.centre == region.centre &&
           last.region.size == region.size && last.radii == radii;
  };
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (same()) return last.packing;
  }
  Packing packing = random_sequential_addition(box, region, radii, seed);
  const std::lock_guard<std::mutex> lock(mutex);
  last = Last{box, region, radii, seed, packing};
  held = true;
  return packing;
}

// The placement of a cloud could not be completed: name the key that set the density.
[[noreturn]] void cloud_jammed(const ParticleSystem& system, const PackingRegion& region, const std::vector<double>& radii,
                               const Packing& packing) {
  const CloudStart& cloud = std::get<CloudStart>(system.start);
  const int d = system.box.dimension;
  std::string key = "volume_fraction", value;
  if (region.shape == PackingRegion::Shape::whole_box) {
    std::ostringstream fraction;  // computed from the box: 6 digits
    fraction << system.volume_fraction();
    value = fraction.str();
  } else {
    key = cloud.size ? "initial.size" : "initial.volume_fraction";
    value = format_value(cloud.size ? *cloud.size : *cloud.volume_fraction);
  }
  double occupied = 0;
  for (double r : radii) occupied += particle_volume(d, r);
  const double fraction =
      occupied / (region.shape == PackingRegion::Shape::whole_box ? system.box.volume() : region.volume(d));
  // The particle that failed is the next one in placement order (larger radii first).
  std::vector<double> sorted = radii;
  std::sort(sorted.begin(), sorted.end(), std::greater<>());
  const double failed = sorted[packing.placed];
  std::ostringstream allowed;
  allowed << "a cloud that random sequential addition can place: ";
  double room = region.size;  // the widest particle the region holds
  if (region.shape == PackingRegion::Shape::whole_box) {
    room = std::numeric_limits<double>::infinity();
    if (system.box.boundary == Boundary::reflecting)
      for (int a = 0; a < d; ++a) room = std::min(room, system.box.side[a]);
  }
  if (2 * failed >= room)
    allowed << "a particle of radius " << failed << " does not fit in the region (width " << room << ")";
  else
    allowed << "particle " << packing.placed + 1 << " of " << system.count << " (radius " << failed
            << ") found no free place in " << packing_attempts_per_particle << " trials at volume fraction "
            << fraction << " of its region (RSA jams near " << rsa_jamming_2d << " for equal discs in 2-D and near "
            << rsa_jamming_3d << " for equal spheres in 3-D)";
  throw InputError(key, value, allowed.str());
}

}  // namespace

ParticleStart ParticleSystem::initial_state(std::size_t realization) const {
  if (const StartFile* file = file_of(*this)) return file->particles;
  const std::uint64_t run = run_seed(seed, realization);
  ParticleStart s;
  s.radii = radii_of(*this, run);
  s.masses = masses_of(*this, run, s.radii);
  s.velocities = velocities_of(*this, run, s.masses);
  if (start_kind() == StartKind::lattice) {
    s.positions = lattice_positions(box, count, radius_law.value);
    return s;
  }
  const PackingRegion region = cloud_region();
  Packing packing = placement(box, region, s.radii, stream_seed(run, StartStream::positions));
  if (!packing.complete()) cloud_jammed(*this, region, s.radii, packing);
  s.positions = std::move(packing.positions);
  return s;
}

std::vector<Vector3> ParticleSystem::initial_positions() const {
  if (const StartFile* file = file_of(*this)) return file->particles.positions;
  if (start_kind() != StartKind::lattice)
    throw std::logic_error("ParticleSystem::initial_positions: a cloud start differs between realizations; use initial_state(r)");
  return lattice_positions(box, count, radius_law.value);
}

std::vector<Vector3> ParticleSystem::initial_velocities(std::size_t realization) const {
  if (const StartFile* file = file_of(*this)) return file->particles.velocities;
  const std::uint64_t run = run_seed(seed, realization);
  if (equal_masses()) return velocities_of(*this, run, std::vector<double>(count, 1.0));
  return velocities_of(*this, run, masses_of(*this, run, radii_of(*this, run)));
}

}  // namespace aggkit

#include "particle/common/particle_system.hpp"

#include <cmath>
#include <sstream>

#include "analysis/input_error.hpp"
#include "particle/common/seeds.hpp"

namespace aggkit {

void ParticleSystem::validate() const {
  box.validate();
  if (count < 2) throw InputError("particles.count", std::to_string(count), "an integer >= 2");
  if (count >= 0xffffffffu) throw InputError("particles.count", std::to_string(count), "fewer than 2^32 - 1 particles");
  if (!(radius > 0) || !std::isfinite(radius)) throw InputError("particles.radius", format_value(radius), "a finite radius > 0");
  if (!(speed > 0) || !std::isfinite(speed)) throw InputError("particles.initial.speed", format_value(speed), "a finite speed > 0");
  if (realizations < 1) throw InputError("particles.realizations", std::to_string(realizations), "an integer >= 1");
  if (box.boundary == Boundary::periodic)
    for (int d = 0; d < box.dimension; ++d)
      if (box.side[d] < 6 * radius)
        throw InputError("particles.box", format_value(box.side[d]), "periodic box sides of at least 6R = " + format_value(6 * radius));
  try {
    (void)lattice_positions(box, count, radius);
  } catch (const InputError&) {
    throw InputError("particles.volume_fraction", format_value(volume_fraction()),
                     "a volume fraction at which the " + std::to_string(count) +
                         " particles fit on the square/cubic lattice without overlapping (about pi/4 in 2-D, pi/6 in 3-D at most)");
  }
}

std::vector<Vector3> ParticleSystem::initial_velocities(std::size_t realization) const {
  return aggkit::initial_velocities(box.dimension, count, velocities, speed, run_seed(seed, realization));
}

std::string ParticleSystem::describe() const {
  std::ostringstream out;
  out << count << " particles, " << box.dimension << "-D, R = " << radius << ", volume fraction "
      << volume_fraction() << ", " << to_string(box.boundary) << ", "
      << (velocities == VelocityLaw::fixed_speed ? "speed " : "uniform components ±") << speed;
  if (thermalize > 0) out << ", thermalised (" << thermalize << " collisions each)";
  if (realizations > 1) out << ", " << realizations << " realizations";
  return out.str();
}

}  // namespace aggkit

#pragma once
// A particle system as a scene describes it ([particles]): N equal particles of radius R in a square/cubic
// box (side from the volume fraction, or given), boundary, lattice start, velocity law, thermalisation and
// the seeds of independent realizations. Shared by the particle engines (ED, TS, DEM).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "particle/common/box.hpp"
#include "particle/common/initial_state.hpp"

namespace aggkit {

struct ParticleSystem {
  Box box;                    // dimension, sides and boundary
  std::size_t count = 0;      // N
  double radius = 0;          // R (mass 1 per particle)
  VelocityLaw velocities = VelocityLaw::fixed_speed;
  double speed = 1.0;         // fixed speed, or half-width of the uniform components
  std::size_t thermalize = 0;  // elastic collisions per particle before sticking (0: none)
  std::uint64_t seed = 1;
  std::size_t realizations = 1;

  double volume_fraction() const { return aggkit::volume_fraction(box, count, radius); }
  // Throws InputError (keys as in [particles]) for N < 2, R <= 0, a lattice that does not fit, a periodic
  // box narrower than 3 contact distances, speed <= 0 or realizations < 1.
  void validate() const;
  std::vector<Vector3> initial_positions() const { return lattice_positions(box, count, radius); }
  // Independent velocities for realization r = 0, 1, ... (seed mixed with r).
  std::vector<Vector3> initial_velocities(std::size_t realization) const;
  std::string describe() const;  // one line
};

}  // namespace aggkit

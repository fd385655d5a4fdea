#pragma once
// A particle system as a scene describes it ([particles]), shared by the particle engines (ED, TS, DEM):
// N particles in a square/cubic box (side from the volume fraction, or given) with periodic or reflecting
// boundaries, or in open space; per-particle radii and masses (one value, a distribution drawn per
// realization, or masses from a density); the start (a lattice filling the box, a random cloud, or a CSV
// file); the velocity law, thermalisation and the seeds of independent realizations.
//
// Keys in InputError messages are relative to the section ("count", "radius.sd", "initial.volume_fraction");
// the scene reader prefixes "particles.".
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "analysis/option_rows.hpp"
#include "particle/common/box.hpp"
#include "particle/common/initial_state.hpp"
#include "particle/common/particle_start.hpp"
#include "particle/common/property_law.hpp"
#include "particle/common/random_packing.hpp"
#include "particle/common/start_file.hpp"

namespace aggkit {

// Masses: a law of their own (default 1 for every particle), or m = ρ v(R) from a material density ρ
// (v(R) = πR² in 2-D, 4πR³/3 in 3-D).
struct MassLaw {
  PropertyLaw law = PropertyLaw::fixed(1.0);  // used when density is absent
  std::optional<double> density;              // ρ
};

// The starts. A lattice: square/cubic lattice filling the box (particle/common/initial_state.hpp), equal
// radii only.
struct LatticeStart {};

enum class CloudShape { cube, sphere };
// A cloud: positions uniformly random without overlaps (random sequential addition, random_packing.hpp),
// drawn anew for each realization. The region:
//   open boundary       a cube of side `size` (or sphere of diameter `size`) centred at the origin, or sized
//                       so that the expected Σ v_i / region volume = volume_fraction (exactly one of the two);
//   periodic/reflecting cube: the whole box (neither size nor volume_fraction: the box decides);
//                       sphere: centred in the box, diameter `size` or from volume_fraction, inside the box.
struct CloudStart {
  CloudShape shape = CloudShape::cube;
  std::optional<double> size;
  std::optional<double> volume_fraction;
};

// A file: positions, velocities, radii and masses of every particle from a CSV file (start_file.hpp), the
// same for every realization.
struct FileStart {
  StartFile file;
};

struct ParticleSystem {
  Box box;                     // dimension, sides and boundary (sides unused when open)
  std::size_t count = 0;       // N
  PropertyLaw radius_law;      // radii (not used with a file start)
  MassLaw mass_law;            // masses (not used with a file start)
  std::variant<LatticeStart, CloudStart, FileStart> start;
  VelocityLaw velocities = VelocityLaw::fixed_speed;
  double speed = 1.0;          // fixed speed, or half-width of the uniform components; 0: cold start
  // The scalar keys of [particles], declared with their ranges and defaults once, as option rows
  // (particle_system_option_rows): these initial values are the defaults a scene and a sweep use.
  std::size_t thermalize = 0;  // elastic collisions per particle before sticking (0: none; an ED setting)
  std::uint64_t seed = 1;      // realization r runs on run_seed(seed, r) (seeds.hpp)
  std::size_t realizations = 1;

  enum class StartKind { lattice, cloud, file };
  StartKind start_kind() const { return StartKind(start.index()); }

  // Radii: equal_radii() when every particle has the same radius (a fixed radius, or a file whose radii are
  // all equal); mean_radius() is that radius, else the mean of the (truncated) law or of the file's radii.
  bool equal_radii() const;
  double mean_radius() const;
  double largest_radius() const;  // the largest radius a particle can have (+inf for an unbounded law)
  bool equal_masses() const;
  double mean_mass() const;
  // Every velocity zero: speed = 0, or a file whose velocities are all zero.
  bool cold() const;

  // Expected Σ v_i over the particles: N·E[v(R)] (GSL quadrature for a radius distribution), or the file's
  // exact sum.
  double expected_particle_volume() const;
  // Σ v_i / V with the expected Σ v_i: of the box; with an open boundary, of the cloud's region (NaN for a
  // file start in open space, which has no region).
  double volume_fraction() const;
  // The region a cloud start fills (std::logic_error for other starts).
  PackingRegion cloud_region() const;

  // Throws InputError (keys relative to [particles]) for N < 2, bad radius or mass laws, a start that does
  // not fit its boundary (a lattice or a box-filling cloud in open space, a lattice with unequal radii), a
  // lattice that does not fit, a periodic box narrower than 6 largest radii, speed < 0, realizations < 1, a
  // cloud region that does not fit in the box, a cloud that cannot be placed (realization 0 is placed once
  // to find out), and a file whose count differs from `count`, with particles outside the box or
  // overlapping.
  void validate() const;

  // Realization r's start (r = 0, 1, ...): positions, velocities, radii and masses. Velocities come from
  // aggkit::initial_velocities(..., run_seed(seed, r)) (zero for a cold start; with unequal masses and
  // uniform components the mass-weighted mean is removed, so the total momentum is zero); radii, masses and
  // cloud positions come from their own streams (seeds.hpp: stream_seed), so they never shift the
  // velocities. For a fixed radius and a lattice start, positions and velocities are those of
  // initial_positions() and initial_velocities(r). Throws InputError when a cloud cannot be placed.
  ParticleStart initial_state(std::size_t realization) const;

  // The lattice start's positions (a file's positions for a file start; std::logic_error for a cloud,
  // whose positions depend on the realization: use initial_state).
  std::vector<Vector3> initial_positions() const;
  // Realization r's velocities (seed mixed with r), as in initial_state.
  std::vector<Vector3> initial_velocities(std::size_t realization) const;
  std::string describe() const;  // one line
};

// The rows of [particles]' scalar keys (thermalize, seed, realizations), bound to ParticleSystem's fields
// (analysis/option_rows.hpp): the scene reads them through these rows and ParticleSystem::validate checks
// their ranges, so key, range and default are declared here alone.
const OptionRows<ParticleSystem>& particle_system_option_rows();

}  // namespace aggkit

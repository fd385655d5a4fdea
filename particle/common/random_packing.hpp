#pragma once
// Random placement of hard particles without overlaps, and the overlap check of a given configuration.
//
// Random sequential addition (RSA): particles are placed one after another at uniformly random positions
// in the region; a trial position is kept when the new particle overlaps none placed before, otherwise
// another is drawn. Larger particles go first (a small particle fits into gaps a large one cannot use).
// A cell grid with cells at least one largest contact distance wide makes each trial O(1), so N particles
// cost O(N) trials away from jamming. RSA jams — no free place is left for one more particle, however many
// trials — near a volume fraction of 0.547 for equal discs (2-D) and 0.38 for equal spheres (3-D); a spread
// of radii jams somewhat higher. The placement is uniform given the particles placed before, not an
// equilibrium hard-sphere configuration (it has fewer close pairs).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "particle/common/box.hpp"

namespace aggkit {

// Where the particles go.
struct PackingRegion {
  enum class Shape {
    whole_box,  // the box: centres anywhere in a periodic box, at least R from reflecting walls
    cube,       // the square/cube of side `size` centred at `centre`, whole particles inside it
    sphere,     // the disc/sphere of diameter `size` centred at `centre`, whole particles inside it
  };
  Shape shape = Shape::whole_box;
  Vector3 centre{0, 0, 0};
  double size = 0;

  double volume(int dimension) const;  // of a cube or sphere region (area in 2-D)
};

// RSA jamming volume fractions of equal particles (for messages and rough checks).
inline constexpr double rsa_jamming_2d = 0.547;
inline constexpr double rsa_jamming_3d = 0.38;
// Trials allowed for one particle before the placement gives up (the region is then all but jammed).
inline constexpr std::size_t packing_attempts_per_particle = 100000;

struct Packing {
  std::vector<Vector3> positions;  // in the order of the radii; meaningful when complete()
  std::size_t placed = 0;          // particles placed before the placement stopped
  std::size_t attempts = 0;        // trial positions drawn in all
  std::size_t count = 0;           // particles asked for
  bool complete() const { return placed == count; }
};

// Places particles with the given radii by RSA in `region` of `box` (cube and sphere regions must lie inside
// a periodic or reflecting box; with Boundary::open they may be anywhere, and whole_box is not allowed).
// Overlaps are judged on the minimum image in a periodic box. Never throws for a dense packing: the result
// is incomplete when some particle found no place in `attempts_per_particle` trials (or cannot fit at all).
Packing random_sequential_addition(const Box& box, const PackingRegion& region, std::span<const double> radii,
                                   std::uint64_t seed,
                                   std::size_t attempts_per_particle = packing_attempts_per_particle);

// The first pair (i, j), i < j in the order of j, of particles closer than (R_i + R_j)(1 − tolerance)
// (minimum image in a periodic box), or std::nullopt; O(N) expected through a cell grid. The tolerance
// lets touching particles written with rounded coordinates pass.
std::optional<std::pair<std::size_t, std::size_t>> first_overlap(const Box& box, std::span<const Vector3> positions,
                                                                 std::span<const double> radii, double tolerance = 1e-9);

}  // namespace aggkit

#pragma once
// Shape and packing of a particle configuration: the gyration tensor, the relative number of contacts N_c
// and the pair distribution P(r). N_c and P(r) follow the definitions of [Degond2024, eqs. 4.6–4.7]
// (ballistic aggregation of hard discs); the gyration tensor gives their aspect ratio and orientation
// [Degond2024, eqs. 4.4–4.5].
#include <array>
#include <span>
#include <vector>

#include "analysis/particle_configuration.hpp"

namespace aggkit {

// Gyration tensor S_ab = (1/N) Σ_i (x_ia - c_a)(x_ib - c_b), c the centroid, over the first `dimension`
// axes (the points of one cluster, unwrapped if periodic).
struct Gyration {
  std::array<double, 3> eigenvalues{};           // of the gyration tensor, descending
  double aspect_ratio = 1;                       // λ1/λ2 (ratio of eigenvalues; +inf if λ2 = 0 < λ1)
  std::array<double, 3> principal_axis{};        // unit eigenvector of λ1
  double orientation = 0;                        // angle of the principal axis to x (radians, [0, π))
  double radius_of_gyration = 0;                 // sqrt(λ1 + λ2 + λ3)
};
Gyration gyration(std::span<const std::array<double, 3>> points, int dimension);

// N_c = (1/N)(1/N_max) Σ_{i≠j} 1{|Xi−Xj| ≤ factor·R}, N_max = 6 (2-D) or 12 (3-D): the mean number of
// neighbours within factor·R relative to the densest packing's [Degond2024, eq. 4.6]; for particles of
// their own radii within factor·(R_i + R_j)/2. O(N) by a neighbour grid; minimum image when periodic. 0 for
// an empty configuration.
//
// ContactCounting::with_self sums over all (i, j), i = j included, which adds exactly 1/N_max. That is
// the reading under which the published N_c ≈ 0.5 [Degond2024, Sec. 4.2.1, Fig. 7] is what hit-and-stick
// gives: each merge makes one contact, the contact graph is a tree with mean degree 2(N−1)/N, and
// (2(N−1)/N + 1)/6 → 0.5, whereas the i ≠ j sum gives 1/3 (measured: bench/results/log/ed-ballistic-aggregation.md). Eq. 4.6 indeed
// sums over all i, j = 1..N, and the paper expects N_c "between 1/6 and one".
enum class ContactCounting { other_particles, with_self };
double relative_contacts(const ParticleConfiguration& config, double factor = 2.1,
                         ContactCounting counting = ContactCounting::other_particles);

// P(r) = (1/N) Σ_{i≠j} 1{|Xi−Xj| ≤ r} at the given radii (any order, positive), the mean number of other
// particles within r ([Degond2024, eq. 4.7], used there for 2R < r < 20R). O(N · pairs within max r) by a
// neighbour grid with cutoff max r; periodic: minimum-image distances only.
struct PairDistribution { std::vector<double> r; std::vector<double> p; };
PairDistribution pair_distribution(const ParticleConfiguration& config, std::span<const double> r);
// `count` radii evenly spaced on (2R, 20R]: 2R + 18R k/count, k = 1..count (the range of [Degond2024]).
std::vector<double> pair_distribution_radii(double radius, int count = 90);

}  // namespace aggkit

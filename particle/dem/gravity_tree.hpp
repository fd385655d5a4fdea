#pragma once
// Barnes–Hut octree for the self-gravity of the DEM: cells with the mass, centre of mass and traceless
// quadrupole Q_ab = Σ m (3 y_a y_b − |y|² δ_ab) of their particles (y from the centre of mass). Particles are
// walked in groups [Barnes1990]: the cells of at most 64 particles, one walk per group; a cell of side l is
// accepted when l < θ d, d the distance from its centre of mass to the group's bounding box, and it does not
// overlap that box (a criterion at least as strict as each member's own, l < θ r), and acts by its monopole
// and quadrupole,
//   a = −G M d/r³ + G Q d/r⁵ − (5/2) G (dᵀQd) d/r⁷   (d = x − centre of mass);
// otherwise its children are opened, and leaves (≤ 16 particles) act pair by pair with the engine's law
// G m_i m_j/(r² + ε²) along the pair [Trivino2025, eq. 1]. The group's lists are evaluated for each member by
// vectorised loops (compiled for several vector units, chosen at load time: particle/common/simd_clones.hpp). Accepted cells use the Newtonian expansion: they lie at r > l/θ, where the softening's
// relative effect ε²/r² is negligible beside the expansion error. Each group's walk and each member's sum
// are independent of the others: any thread count gives the same forces. Unlike the symmetric direct sum
// the tree does not conserve momentum exactly (the expansion error, which falls with θ).
#include <cstddef>
#include <vector>

#include "particle/common/vector3.hpp"
#include "particle/common/worker_pool.hpp"

namespace aggkit {

// Forces (not accelerations) on every particle, added to `force`. θ in (0, 1].
void tree_gravity(const std::vector<Vector3>& x, const std::vector<double>& m, double G, double softening, double opening_angle,
                  std::size_t threads, std::vector<Vector3>& force);
// The same on a worker pool (nullptr: the calling thread alone).
void tree_gravity(const std::vector<Vector3>& x, const std::vector<double>& m, double G, double softening, double opening_angle,
                  WorkerPool* pool, std::vector<Vector3>& force);

}  // namespace aggkit

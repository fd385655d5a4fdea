#pragma once
// Direct summation of the DEM's pairwise gravity G m_i m_j / (r² + ε²) along each pair [Trivino2025, eq. 1],
// every pair once, the force added to both particles with opposite signs (total momentum kept to round-off).
// The pairs are cut into a fixed tiling of K × K blocks of particles (K from N only: blocks of at least 64
// particles, at most 16 blocks); each tile accumulates into its own buffers and the buffers are reduced per
// particle in tile order, so the forces do not depend on the thread count. The inner loop runs on arrays
// of coordinates (structure of arrays) and is vectorised (OpenMP simd with a fixed lane order, compiled for
// several vector units and chosen at load time, particle/common/simd_clones.hpp: one machine gives the same
// bits for any thread count).
#include <cstddef>
#include <vector>

#include "particle/common/vector3.hpp"
#include "particle/common/worker_pool.hpp"

namespace aggkit {

// Forces (not accelerations) on every particle, added to `force`; `threads` >= 1.
void direct_gravity(const std::vector<Vector3>& x, const std::vector<double>& m, double G, double softening, std::size_t threads,
                    std::vector<Vector3>& force);
// The same on a worker pool (nullptr: the calling thread alone).
void direct_gravity(const std::vector<Vector3>& x, const std::vector<double>& m, double G, double softening, WorkerPool* pool,
                    std::vector<Vector3>& force);

}  // namespace aggkit

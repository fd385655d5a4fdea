#pragma once
// Starting configurations of the particle engines: particles on a square/cubic lattice filling the box,
// velocities of fixed speed with uniformly random directions or with independent uniform components
// (total momentum then removed). Seeded and reproducible (std::mt19937_64).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "particle/common/box.hpp"

namespace aggkit {

// N sites of the lattice of n = ceil(N^{1/d}) sites per axis with spacing a_d = L_d/n, at (k + 1/2) a_d
// (the first N sites in lexicographic order). Throws InputError when the spacing is below 2R (overlap).
std::vector<Vector3> lattice_positions(const Box& box, std::size_t count, double radius);

enum class VelocityLaw {
  fixed_speed,         // |v| = speed, direction uniform on the circle/sphere
  uniform_components,  // v_d uniform in [-speed, speed], then the mean velocity subtracted (zero momentum)
};

std::vector<Vector3> initial_velocities(int dimension, std::size_t count, VelocityLaw law, double speed,
                                        std::uint64_t seed);

}  // namespace aggkit

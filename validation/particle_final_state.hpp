#pragma once
// Observables of the final configuration of a particle engine (scene `observe.final`), written to
// <engine>/final.json:
//   clusters, mean_cluster_size, largest_cluster (its particle count), kinetic_energy
//   contacts                 relative contacts per sphere N_c (α_R = 2.1, N_max = 6 or 12; analysis/shape.hpp)
//   contacts_with_self       N_c with the i = j terms counted (+1/N_max): the reading under which Degond et
//                            al.'s published N_c ≈ 0.5 matches hit-and-stick aggregates (analysis/shape.hpp)
//   aspect_ratio, orientation, radius_of_gyration   gyration tensor of the largest cluster
//   fractal_dimension_box    box counting of the largest cluster (grid L/2^m over the box side for reflecting
//                            walls, as in Degond et al.; over its own bounding square/cube when periodic)
//   fractal_dimension_mass   mass–radius N(r) of the largest cluster around interior particles
// The fractal dimensions also give <name>_error (standard error of the fitted slope) and the fit range
// <name>_fit_min, <name>_fit_max (lengths).
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace aggkit {

struct ParticleConfiguration;

const std::vector<std::string>& final_state_observables();

struct FinalConfiguration {
  const ParticleConfiguration& config;                       // all particles, wrapped into the box
  std::span<const std::uint32_t> cluster;                    // label per particle, 0..C-1
  std::span<const std::array<double, 3>> largest_cluster;    // the largest cluster, contiguous (unwrapped)
  double kinetic_energy = 0;
};

// (key, value) for each requested name, in order, with the extra fit keys after a fractal dimension.
std::vector<std::pair<std::string, double>> final_state_values(std::span<const std::string> names,
                                                               const FinalConfiguration& final);

}  // namespace aggkit

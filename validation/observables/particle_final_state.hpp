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
// Function-valued ones (profiles) go to <engine>/<name>.csv instead, the mean over the realizations and,
// with several, <column>_stderr:
//   pair_distribution        columns r, P: P(r) = (1/N) Σ_{i≠j} 1{|Xi−Xj| <= r} over all particles at 90
//                            radii evenly spaced on (2R, 20R] (Degond et al.; analysis/shape.hpp)
#include <array>
#include <cstdint>
#include <filesystem>
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

// (key, value) for each requested scalar name, in order, with the extra fit keys after a fractal dimension.
std::vector<std::pair<std::string, double>> final_state_values(std::span<const std::string> names,
                                                               const FinalConfiguration& final);

// One profile of one realization: y against x.
struct FinalProfile {
  std::string name, x_name, y_name;
  std::vector<double> x, y;
};
// The requested profiles, in order (the scalar names are skipped).
std::vector<FinalProfile> final_profiles(std::span<const std::string> names, const FinalConfiguration& final);
// Writes <folder>/<name>.csv for each profile from its realizations (same x in each): x, mean y and, with
// more than one realization, y_stderr. `realizations[r]` is final_profiles' result for realization r.
void write_final_profiles(const std::filesystem::path& folder, const std::vector<std::vector<FinalProfile>>& realizations);

}  // namespace aggkit

#pragma once
// The state of one DSMC realisation at an output time: particle counts per size in a volume V, so that
// densities are n_k = count_k / V (the simulated system stands for unit volume of the kinetic model).
#include <cstdint>
#include <utility>
#include <vector>

namespace aggkit::dsmc {

struct Snapshot {
  double time = 0.0;
  double volume = 1.0;
  std::uint64_t particles = 0;
  std::uint64_t leaked_mass = 0;  // mass removed by a `drop` truncation (scaled like the particles)
  std::vector<std::pair<std::uint64_t, std::uint64_t>> groups;  // (size, count), sizes increasing, distinct

  double moment(double p) const;            // M_p = Σ k^p n_k (compensated sum)
  double density(std::uint64_t k) const;    // n_k
  double leaked_density() const { return double(leaked_mass) / volume; }
  std::uint64_t mass() const;               // Σ k count_k (exact)
};

}  // namespace aggkit::dsmc

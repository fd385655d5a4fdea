#pragma once
// The state of a particle engine at an output time, as the series observables see it: the cluster-size
// distribution normalised per initial particle, n_k = (clusters of size k)/N — so M1 = 1 and M0 = C/N match
// a kinetic run from unit monomer density — the number of clusters C, the mean cluster size N/C and the
// kinetic energy. Averages over realizations are taken field by field (n_k, C, N/C, E).
#include <cstddef>
#include <span>
#include <vector>

#include "validation/observables/system_state.hpp"

namespace aggkit {

class ParticleState final : public SystemState {
 public:
  ParticleState() = default;
  // From the sizes of the clusters (any order) and the kinetic energy.
  ParticleState(std::span<const std::size_t> cluster_sizes, double kinetic_energy);

  double moment(double p) const override;
  double density(std::size_t k) const override { return k >= 1 && k <= n_.size() ? n_[k - 1] : 0.0; }
  double leaked_mass() const override { return 0.0; }
  std::vector<double> distribution() const override { return n_; }
  double clusters() const override { return clusters_; }
  double kinetic_energy() const override { return energy_; }
  double mean_cluster_size() const override { return mean_size_; }

  // Running sums for averages: add states, then scale by 1/realizations.
  ParticleState& operator+=(const ParticleState& other);
  ParticleState& operator*=(double factor);

 private:
  std::vector<double> n_;  // n_1..n_{largest size}
  double clusters_ = 0, energy_ = 0, mean_size_ = 0;
};

}  // namespace aggkit

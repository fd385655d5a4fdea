#include "validation/observables/particle_state.hpp"

#include <algorithm>

#include "analysis/moments.hpp"

namespace aggkit {

ParticleState::ParticleState(std::span<const std::size_t> cluster_sizes, double kinetic_energy)
    : clusters_(double(cluster_sizes.size())), energy_(kinetic_energy) {
  std::size_t particles = 0, largest = 0;
  for (auto s : cluster_sizes) {
    particles += s;
    largest = std::max(largest, s);
  }
  n_.assign(largest, 0.0);
  for (auto s : cluster_sizes)
    if (s > 0) n_[s - 1] += 1.0 / double(particles);
  mean_size_ = clusters_ > 0 ? double(particles) / clusters_ : 0.0;
}

double ParticleState::moment(double p) const { return aggkit::moment(n_, p); }

ParticleState& ParticleState::operator+=(const ParticleState& other) {
  if (other.n_.size() > n_.size()) n_.resize(other.n_.size(), 0.0);
  for (std::size_t k = 0; k < other.n_.size(); ++k) n_[k] += other.n_[k];
  clusters_ += other.clusters_;
  energy_ += other.energy_;
  mean_size_ += other.mean_size_;
  return *this;
}

ParticleState& ParticleState::operator*=(double factor) {
  for (auto& x : n_) x *= factor;
  clusters_ *= factor;
  energy_ *= factor;
  mean_size_ *= factor;
  return *this;
}

}  // namespace aggkit

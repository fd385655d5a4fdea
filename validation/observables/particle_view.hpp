#pragma once
// The configuration of a particle engine (ED, TS, DEM) as the observables read it.
//   ParticleSource: the one small interface an engine implements to expose a realization's configuration.
//   ParticleView:   the observed state built on it; each piece (configuration, velocities, masses, cluster
//                   labels, the largest cluster) is asked of the engine only when an observable needs it,
//                   and then once.
// The size distribution of a particle state is per initial particle, n_k = (clusters of size k)/N, so that
// M1 = 1 and M0 = C/N compare with a kinetic run from unit monomer density.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "analysis/particle_configuration.hpp"
#include "particle/common/vector3.hpp"
#include "validation/observables/observed_state.hpp"

namespace aggkit {

// What an engine of colliding particles has accumulated since its clock started (t = 0, after any
// preparation such as ED's thermalisation), for the collision frequency and the pressure from the virial
// theorem [Allen2017, ch. 2]:  d P V t = ∫ Σ_i m_i |v_i|² dt + W.
struct CollisionStatistics {
  double time = 0;        // t, the length of the window
  double collisions = 0;  // pair collisions begun in it
  // W = ∫ Σ_{pairs} r_ij · F_ij dt (r_ij = x_i − x_j, F_ij the force of j on i; minimum image): for hard
  // spheres the impulsive limit Σ_collisions r_ij · Δp_i.
  double virial = 0;
  double kinetic = 0;     // ∫ Σ_i m_i |v_i|² dt (twice the time integral of the kinetic energy)
};

class ParticleSource {
 public:
  virtual ~ParticleSource() = default;
  virtual ParticleConfiguration configuration() const = 0;        // every particle, wrapped into the box
  virtual std::vector<Vector3> velocities() const = 0;            // per particle
  virtual std::vector<double> masses() const = 0;                 // per particle
  virtual std::vector<std::uint32_t> cluster_labels() const = 0;  // per particle, labels 0..C-1
  // The particles of the largest cluster, unwrapped so that the cluster is contiguous. By default from
  // the labels and analysis/clusters.hpp's unwrap_cluster with contact distance 2.1 R.
  virtual std::vector<Vector3> largest_cluster() const;
  // Σ ½ m |v|²; by default over the particles. An engine of rigid clusters may sum over clusters instead.
  virtual double kinetic_energy() const;
  // Engines that give need::collisions (observable.hpp) override this; std::nullopt otherwise.
  virtual std::optional<CollisionStatistics> collision_statistics() const { return std::nullopt; }
};

class ParticleView final : public ObservedState {
 public:
  explicit ParticleView(const ParticleSource& source) : source_(&source) {}

  std::vector<double> distribution() const override { return size_distribution(); }
  double moment(double p) const override;
  double density(std::size_t k) const override;
  const ParticleView* particles() const override { return this; }

  const std::vector<double>& size_distribution() const;  // n_1..n_{largest}, per initial particle
  const ParticleConfiguration& configuration() const;
  std::span<const Vector3> velocities() const;
  std::span<const double> masses() const;
  std::span<const std::uint32_t> cluster_labels() const;
  std::span<const std::size_t> cluster_sizes() const;  // index = label
  std::size_t count() const { return cluster_labels().size(); }  // particles
  std::size_t clusters() const { return cluster_sizes().size(); }
  std::span<const Vector3> largest_cluster() const;
  double kinetic_energy() const;
  const std::optional<CollisionStatistics>& collision_statistics() const;

 private:
  const ParticleSource* source_;
  mutable std::optional<std::vector<double>> distribution_;
  mutable std::optional<ParticleConfiguration> configuration_;
  mutable std::optional<std::vector<Vector3>> velocities_;
  mutable std::optional<std::vector<double>> masses_;
  mutable std::optional<std::vector<std::uint32_t>> labels_;
  mutable std::optional<std::vector<std::size_t>> sizes_;
  mutable std::optional<std::vector<Vector3>> largest_;
  mutable std::optional<double> energy_;
  mutable std::optional<std::optional<CollisionStatistics>> collisions_;
};

}  // namespace aggkit

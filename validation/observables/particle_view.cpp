#include "validation/observables/particle_view.hpp"

#include <algorithm>

#include "analysis/clusters.hpp"
#include "analysis/moments.hpp"

namespace aggkit {

namespace {

template <class T, class F>
const T& cached(std::optional<T>& slot, F&& compute) {
  if (!slot) slot.emplace(compute());
  return *slot;
}

}  // namespace

std::vector<Vector3> ParticleSource::largest_cluster() const {
  const ParticleConfiguration config = configuration();
  const std::vector<std::uint32_t> labels = cluster_labels();
  const std::vector<std::size_t> sizes = aggkit::cluster_sizes(labels);
  const auto largest = std::uint32_t(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
  std::vector<std::size_t> members;
  for (std::size_t i = 0; i < labels.size(); ++i)
    if (labels[i] == largest) members.push_back(i);
  return unwrap_cluster(config, members, 2.1 * config.radius);
}

double ParticleSource::kinetic_energy() const {
  const std::vector<Vector3> v = velocities();
  const std::vector<double> m = masses();
  double energy = 0;
  for (std::size_t i = 0; i < v.size(); ++i) energy += 0.5 * m[i] * dot(v[i], v[i]);
  return energy;
}

const std::vector<double>& ParticleView::size_distribution() const {
  return cached(distribution_, [&] {
    const std::span<const std::size_t> sizes = cluster_sizes();
    std::size_t particles = 0, largest = 0;
    for (auto s : sizes) particles += s, largest = std::max(largest, s);
    std::vector<double> n(largest, 0.0);
    for (auto s : sizes)
      if (s > 0) n[s - 1] += 1.0 / double(particles);
    return n;
  });
}

double ParticleView::moment(double p) const { return aggkit::moment(size_distribution(), p); }

double ParticleView::density(std::size_t k) const {
  const std::vector<double>& n = size_distribution();
  return k >= 1 && k <= n.size() ? n[k - 1] : 0.0;
}

const ParticleConfiguration& ParticleView::configuration() const {
  return cached(configuration_, [&] { return source_->configuration(); });
}
std::span<const Vector3> ParticleView::velocities() const {
  return cached(velocities_, [&] { return source_->velocities(); });
}
std::span<const double> ParticleView::masses() const {
  return cached(masses_, [&] { return source_->masses(); });
}
std::span<const std::uint32_t> ParticleView::cluster_labels() const {
  return cached(labels_, [&] { return source_->cluster_labels(); });
}
std::span<const std::size_t> ParticleView::cluster_sizes() const {
  return cached(sizes_, [&] { return aggkit::cluster_sizes(cluster_labels()); });
}
std::span<const Vector3> ParticleView::largest_cluster() const {
  return cached(largest_, [&] { return source_->largest_cluster(); });
}
double ParticleView::kinetic_energy() const {
  return cached(energy_, [&] { return source_->kinetic_energy(); });
}
const std::optional<CollisionStatistics>& ParticleView::collision_statistics() const {
  return cached(collisions_, [&] { return source_->collision_statistics(); });
}

}  // namespace aggkit

#pragma once
// Clusters of a particle configuration: particles in contact belong to one
// cluster; contacts are found with a neighbour grid (O(N)) and joined by union–find.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "analysis/particle_configuration.hpp"

namespace aggkit {

// Disjoint sets with union by size and path halving (amortised near-constant time per operation).
class UnionFind {
 public:
  explicit UnionFind(std::size_t n);
  std::size_t find(std::size_t);
  bool unite(std::size_t, std::size_t);  // false if already in one set
  std::size_t components() const;
  std::size_t size_of(std::size_t element);  // members of the element's set

 private:
  std::vector<std::size_t> parent_, size_;
  std::size_t components_;
};

// Cluster labels 0..C-1 (by first appearance) from contacts |Xi - Xj| <= contact_distance, scaled to
// (R_i + R_j)/2R for particles of their own radii (particle_configuration.hpp: for_each_contact; neighbour
// grid, O(N)); minimum image when periodic.
std::vector<std::uint32_t> contact_clusters(const ParticleConfiguration& config, double contact_distance);
std::vector<std::size_t> cluster_sizes(std::span<const std::uint32_t> labels);  // index = label
// The particles of each cluster, ascending (index = label).
std::vector<std::vector<std::size_t>> cluster_members(std::span<const std::uint32_t> labels);

struct SizeDistribution {                        // over clusters
  std::vector<std::size_t> size;                 // distinct sizes, ascending
  std::vector<double> pdf;                       // fraction of clusters with that size
  std::vector<double> cdf;                       // cumulative
};
SizeDistribution size_distribution(std::span<const std::size_t> sizes);
double mean_cluster_size(std::span<const std::size_t> sizes);   // particles per cluster, Σ s / C

// Positions of the members of one cluster made contiguous across periodic boundaries (walk over contacts):
// members[0] keeps its position, every other member is placed at the minimum image relative to the
// contact through which the breadth-first walk reaches it. Without periodicity the positions are copied.
// Throws InputError if the members are not connected by contacts. A cluster that percolates through the
// periodic box has no unique unwrapping; the walk's spanning tree then decides.
std::vector<std::array<double, 3>> unwrap_cluster(const ParticleConfiguration& config,
                                                  std::span<const std::size_t> members,
                                                  double contact_distance);

// The members of the largest cluster (the lowest label among equals), unwrapped as above: the input of
// gyration() and the fractal dimensions for "the final aggregate" of a run. Empty if there are no particles.
std::vector<std::array<double, 3>> largest_cluster(const ParticleConfiguration& config,
                                                   std::span<const std::uint32_t> labels, double contact_distance);

}  // namespace aggkit

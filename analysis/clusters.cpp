#include "analysis/clusters.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>
#include <string>

#include "analysis/input_error.hpp"
#include "analysis/neighbour_grid.hpp"

namespace aggkit {

UnionFind::UnionFind(std::size_t n) : parent_(n), size_(n, 1), components_(n) {
  std::iota(parent_.begin(), parent_.end(), std::size_t{0});
}

std::size_t UnionFind::find(std::size_t x) {
  while (parent_[x] != x) {
    parent_[x] = parent_[parent_[x]];  // path halving
    x = parent_[x];
  }
  return x;
}

bool UnionFind::unite(std::size_t a, std::size_t b) {
  a = find(a), b = find(b);
  if (a == b) return false;
  if (size_[a] < size_[b]) std::swap(a, b);
  parent_[b] = a;
  size_[a] += size_[b];
  --components_;
  return true;
}

std::size_t UnionFind::components() const { return components_; }

std::size_t UnionFind::size_of(std::size_t element) { return size_[find(element)]; }

namespace {
void check_contact_distance(double contact_distance) {
  if (!(contact_distance > 0) || !std::isfinite(contact_distance))
    throw InputError("contact_distance", format_value(contact_distance), "must be positive and finite");
}
}  // namespace

std::vector<std::uint32_t> contact_clusters(const ParticleConfiguration& config, double contact_distance) {
  check_configuration(config);
  check_contact_distance(contact_distance);
  const std::size_t n = config.positions.size();
  if (n > std::numeric_limits<std::uint32_t>::max())
    throw InputError("positions", std::to_string(n) + " particles", "at most 2^32 - 1 particles are labelled");
  UnionFind sets(n);
  for_each_contact(config, config.positions, config.radii, contact_distance,
                   [&](std::size_t i, std::size_t j, const auto&, double) { sets.unite(i, j); });
  std::vector<std::uint32_t> label_of_root(n, std::numeric_limits<std::uint32_t>::max());
  std::vector<std::uint32_t> labels(n);
  std::uint32_t next = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t& label = label_of_root[sets.find(i)];
    if (label == std::numeric_limits<std::uint32_t>::max()) label = next++;
    labels[i] = label;
  }
  return labels;
}

std::vector<std::size_t> cluster_sizes(std::span<const std::uint32_t> labels) {
  std::vector<std::size_t> sizes;
  for (std::uint32_t label : labels) {
    if (label >= sizes.size()) sizes.resize(std::size_t(label) + 1, 0);
    ++sizes[label];
  }
  return sizes;
}

std::vector<std::vector<std::size_t>> cluster_members(std::span<const std::uint32_t> labels) {
  const std::vector<std::size_t> sizes = cluster_sizes(labels);
  std::vector<std::vector<std::size_t>> members(sizes.size());
  for (std::size_t c = 0; c < sizes.size(); ++c) members[c].reserve(sizes[c]);
  for (std::size_t i = 0; i < labels.size(); ++i) members[labels[i]].push_back(i);
  return members;
}

SizeDistribution size_distribution(std::span<const std::size_t> sizes) {
  std::map<std::size_t, std::size_t> clusters_of_size;
  std::size_t clusters = 0;
  for (std::size_t s : sizes)
    if (s > 0) ++clusters_of_size[s], ++clusters;  // labels without members are not clusters
  SizeDistribution distribution;
  std::size_t cumulative = 0;
  for (const auto& [size, count] : clusters_of_size) {
    cumulative += count;
    distribution.size.push_back(size);
    distribution.pdf.push_back(double(count) / double(clusters));
    distribution.cdf.push_back(double(cumulative) / double(clusters));  // exact ratio: the last is 1
  }
  return distribution;
}

double mean_cluster_size(std::span<const std::size_t> sizes) {
  std::size_t particles = 0, clusters = 0;
  for (std::size_t s : sizes)
    if (s > 0) particles += s, ++clusters;
  return clusters == 0 ? 0.0 : double(particles) / double(clusters);
}

std::vector<std::array<double, 3>> unwrap_cluster(const ParticleConfiguration& config,
                                                  std::span<const std::size_t> members,
                                                  double contact_distance) {
  check_configuration(config);
  check_contact_distance(contact_distance);
  std::vector<std::array<double, 3>> points;
  points.reserve(members.size());
  for (std::size_t m : members) {
    if (m >= config.positions.size())
      throw InputError("members", std::to_string(m),
                       "is not a particle index (there are " + std::to_string(config.positions.size()) + ")");
    points.push_back(config.positions[m]);
  }
  if (!config.periodic || points.size() < 2) return points;

  // Contact graph among the members (compressed adjacency), then a breadth-first walk from members[0].
  std::vector<std::pair<std::size_t, std::size_t>> edges;
  std::vector<double> radii;  // the members' own radii, if the particles have their own
  if (!config.radii.empty())
    for (std::size_t m : members) radii.push_back(config.radii[m]);
  for_each_contact(config, points, radii, contact_distance,
                   [&](std::size_t i, std::size_t j, const auto&, double) { edges.emplace_back(i, j); });
  std::vector<std::size_t> start(points.size() + 1, 0), adjacent(2 * edges.size());
  for (const auto& [i, j] : edges) ++start[i + 1], ++start[j + 1];
  for (std::size_t k = 0; k < points.size(); ++k) start[k + 1] += start[k];
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (const auto& [i, j] : edges) adjacent[fill[i]++] = j, adjacent[fill[j]++] = i;

  std::vector<std::array<double, 3>> unwrapped(points.size());
  std::vector<char> reached(points.size(), 0);
  std::vector<std::size_t> queue{0};
  unwrapped[0] = points[0];
  reached[0] = 1;
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const std::size_t i = queue[head];
    for (std::size_t k = start[i]; k < start[i + 1]; ++k) {
      const std::size_t j = adjacent[k];
      if (reached[j]) continue;
      const std::array<double, 3> d = separation(config, points[i], points[j]);
      for (int a = 0; a < 3; ++a) unwrapped[j][a] = unwrapped[i][a] + (a < config.dimension ? d[a] : 0.0);
      if (config.dimension == 2) unwrapped[j][2] = points[j][2];
      reached[j] = 1;
      queue.push_back(j);
    }
  }
  if (queue.size() != points.size())
    throw InputError("members", std::to_string(points.size()) + " particles",
                     "are not one cluster: only " + std::to_string(queue.size()) +
                         " are connected by contacts to the first");
  return unwrapped;
}

std::vector<std::array<double, 3>> largest_cluster(const ParticleConfiguration& config,
                                                   std::span<const std::uint32_t> labels, double contact_distance) {
  if (labels.size() != config.positions.size())
    throw InputError("labels", std::to_string(labels.size()) + " labels",
                     "needs one label per particle (" + std::to_string(config.positions.size()) + ")");
  const std::vector<std::size_t> sizes = cluster_sizes(labels);
  if (sizes.empty()) return {};
  const std::uint32_t largest = std::uint32_t(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
  std::vector<std::size_t> members;
  members.reserve(sizes[largest]);
  for (std::size_t i = 0; i < labels.size(); ++i)
    if (labels[i] == largest) members.push_back(i);
  return unwrap_cluster(config, members, contact_distance);
}

}  // namespace aggkit

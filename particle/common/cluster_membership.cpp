#include "particle/common/cluster_membership.hpp"

#include <numeric>

namespace aggkit {

ClusterMembership::ClusterMembership(std::size_t particles)
    : cluster_(particles), first_(particles), last_(particles), next_(particles, none), size_(particles, 1),
      clusters_(particles) {
  std::iota(cluster_.begin(), cluster_.end(), 0u);
  std::iota(first_.begin(), first_.end(), 0u);
  std::iota(last_.begin(), last_.end(), 0u);
}

std::vector<std::uint32_t> ClusterMembership::labels() const {
  std::vector<std::uint32_t> label_of_cluster(cluster_.size(), none), labels(cluster_.size());
  std::uint32_t next_label = 0;
  for (std::size_t p = 0; p < cluster_.size(); ++p) {
    std::uint32_t& l = label_of_cluster[cluster_[p]];
    if (l == none) l = next_label++;
    labels[p] = l;
  }
  return labels;
}

}  // namespace aggkit

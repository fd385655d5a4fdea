#pragma once
// Particles grouped into clusters that only ever merge: each cluster's members form an intrusive linked
// list, so a merge splices two lists in O(size of the smaller one) (its members are relabelled).
// Cluster ids are the ids of their first particles; a merged-away id stays empty.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "particle/common/checkpoint.hpp"

namespace aggkit {

class ClusterMembership {
 public:
  static constexpr std::uint32_t none = 0xffffffffu;

  explicit ClusterMembership(std::size_t particles);  // every particle its own cluster

  std::uint32_t cluster_of(std::uint32_t particle) const { return cluster_[particle]; }
  std::size_t size(std::uint32_t cluster) const { return size_[cluster]; }
  std::size_t clusters() const { return clusters_; }
  std::size_t particles() const { return cluster_.size(); }
  std::uint32_t first(std::uint32_t cluster) const { return first_[cluster]; }
  std::uint32_t next(std::uint32_t particle) const { return next_[particle]; }

  // Merges `absorbed` into `survivor` (different clusters); `relabel(p)` is called for each particle of
  // `absorbed` after its label changed. Callers choose the larger cluster as survivor.
  template <class F>
  void merge(std::uint32_t survivor, std::uint32_t absorbed, F&& relabel) {
    for (std::uint32_t p = first_[absorbed]; p != none; p = next_[p]) {
      cluster_[p] = survivor;
      relabel(p);
    }
    next_[last_[survivor]] = first_[absorbed];
    last_[survivor] = last_[absorbed];
    size_[survivor] += size_[absorbed];
    size_[absorbed] = 0;
    first_[absorbed] = last_[absorbed] = none;
    --clusters_;
  }

  // Labels 0..C-1 in order of first appearance over the particles, and the size of each label.
  std::vector<std::uint32_t> labels() const;

  // Checkpoints: the membership lists as they are (their order is that of the merges).
  void save(StateWriter& out) const {
    out.put(cluster_);
    out.put(first_);
    out.put(last_);
    out.put(next_);
    out.put(size_);
    out.put(std::uint64_t(clusters_));
  }
  void restore(StateReader& in) {
    const std::size_t n = cluster_.size();
    in.get(cluster_);
    in.get(first_);
    in.get(last_);
    in.get(next_);
    in.get(size_);
    clusters_ = std::size_t(in.read<std::uint64_t>());
    if (cluster_.size() != n || first_.size() != n || last_.size() != n || next_.size() != n || size_.size() != n || clusters_ > n)
      throw CheckpointError("the checkpoint's cluster membership has another number of particles");
  }

 private:
  std::vector<std::uint32_t> cluster_, first_, last_, next_;
  std::vector<std::size_t> size_;
  std::size_t clusters_ = 0;
};

}  // namespace aggkit

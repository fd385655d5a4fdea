// Cluster membership: merges splice member lists and relabel the absorbed particles.
#include <catch2/catch.hpp>
#include <vector>

#include "particle/common/cluster_membership.hpp"

using namespace aggkit;

TEST_CASE("merges relabel the absorbed cluster and keep every member", "[particle_common][clusters]") {
  ClusterMembership m(5);
  CHECK(m.clusters() == 5);
  std::vector<std::uint32_t> relabelled;
  m.merge(0, 3, [&](std::uint32_t p) { relabelled.push_back(p); });
  m.merge(4, 1, [&](std::uint32_t p) { relabelled.push_back(p); });
  m.merge(0, 4, [&](std::uint32_t p) { relabelled.push_back(p); });
  CHECK(relabelled == std::vector<std::uint32_t>{3, 1, 4, 1});
  CHECK(m.clusters() == 2);
  CHECK(m.size(0) == 4);
  CHECK(m.size(4) == 0);
  std::vector<std::uint32_t> members;
  for (auto p = m.first(0); p != ClusterMembership::none; p = m.next(p)) members.push_back(p);
  CHECK(members == std::vector<std::uint32_t>{0, 3, 4, 1});
  CHECK(m.labels() == std::vector<std::uint32_t>{0, 0, 1, 0, 0});
}

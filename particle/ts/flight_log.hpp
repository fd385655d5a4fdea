#pragma once
// The spheres' positions in the time-stepping engine, with its quiet flights logged rather than applied
// (time_stepping_aggregation.hpp, "Quiet flights are rigid-body moves"): a flight within the safe time is
// logged (its Δt); a cluster's spheres are brought up to date by replaying the logged flights in order with
// the arithmetic of an applied flight (x ← x + Δt V, wrapped on periodic boxes), so the run is the same to
// the bit. The clusters' extents at their last update, shifted by their flight since, find in O(clusters)
// those a logged flight may bring to a wall.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "particle/common/box.hpp"
#include "particle/common/cluster_membership.hpp"
#include "particle/common/worker_pool.hpp"

namespace aggkit {

class FlightLog {
 public:
  FlightLog(const Box& box, double radius, std::span<const Vector3> positions);

  // Per sphere: its position (wrapped into the box) and its displacement in the last flight (walls
  // included). Up to date for a cluster after sync(cluster), for every sphere after sync_all().
  std::vector<Vector3> x;
  std::vector<Vector3> flown;

  bool empty() const { return logged_.empty(); }  // no flight waits to be replayed
  // Logs a flight of length dt (the log is bounded: a full log is replayed first).
  void log(double dt, const std::vector<Vector3>& velocity, const ClusterMembership& members, WorkerPool* pool);
  // Replays the logged flights not yet applied to the spheres of one cluster / of every cluster.
  void sync(std::uint32_t cluster, const std::vector<Vector3>& velocity, const ClusterMembership& members);
  void sync_all(const std::vector<Vector3>& velocity, const ClusterMembership& members, WorkerPool* pool);
  // The live clusters (increasing) whose extent, shifted by their flight since it was measured (dt of the
  // flight just logged included), comes within a margin of a wall: those that may touch one.
  std::vector<std::uint32_t> near_walls(double dt, const std::vector<Vector3>& velocity, const ClusterMembership& members,
                                        const std::vector<std::uint32_t>& live, WorkerPool* pool);
  // The extent of a cluster from its spheres (up to date), its flight since reset.
  void measure_extent(std::uint32_t cluster, const ClusterMembership& members);
  void forget_extents() { extents_ = false; }  // the spheres moved otherwise than by logged flights
  void forget_log();  // a restored state: nothing logged, the extents to be measured again

 private:
  void replay(const std::uint32_t* particles, std::size_t count, std::size_t from, const std::vector<Vector3>& velocity,
              const ClusterMembership& members);  // the logged flights from `from`

  Box box_;
  double radius_;
  std::vector<double> logged_;           // Δt of the quiet flights not yet applied to every sphere
  std::vector<std::uint32_t> applied_;   // per cluster id: how many of them its spheres have had
  std::vector<std::uint32_t> partial_;   // clusters with 0 < applied_ (brought up to date at a wall)
  std::vector<Vector3> extent_low_, extent_high_, drift_;  // per cluster id: extent at its last update, flight since
  bool extents_ = false;                 // extent_low_/high_ hold for every live cluster
};

}  // namespace aggkit

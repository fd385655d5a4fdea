#pragma once
// Event-driven ballistic aggregation ([Degond2024, Sec. 2]; cluster-level events as in [Gonzalez2011,
// Sec. 2]): N equal hard discs (2-D) or spheres (3-D) of radius R and unit mass fly freely; two particles
// of different clusters that touch stick, and their clusters merge into one rigid, non-rotating cluster
// moving with the momentum-weighted mean velocity ([Degond2024, eq. 2.9]; momentum conserved, energy lost).
// With sticking off (thermalisation) collisions are elastic instead (equal masses: normal components swap).
// Walls: periodic, or reflecting (a cluster touching a wall has that velocity component reversed as a whole).
//
// Exactness and cost: only exact events are processed — contacts between particles of different clusters,
// broad-phase grid crossings of cluster bounding boxes, pair checks, wall contacts of clusters — from a heap
// with lazy invalidation (event_queue.hpp). Everything is cluster-level, so moving a rigid cluster costs
// nothing per member: a particle's position is its cluster's origin advanced in free flight plus a fixed
// offset, each cluster indexes its members in its own frame (cluster_index.hpp), and the broad phase is a
// hierarchical grid of cluster bounding boxes (hierarchical_grid.hpp) whose crossings are per cluster.
// For a candidate pair the first time their inflated boxes overlap is found in O(1) (overlap_window.hpp);
// only while they overlap is the exact first contact searched, by casting the smaller cluster's members,
// moving with the relative velocity, through the larger one's index (a DDA over its cells, front-first,
// stopping at the best contact found). Predictions are made at velocity changes (merges, walls, elastic
// collisions), when a pair becomes a candidate and when an overlap window opens or closes. A merge moves the
// smaller cluster's members into the larger one's index. Time is kept in long double: positions at 1e9
// collision times still resolve contacts to ~1e-10 R.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <utility>
#include <vector>

#include "particle/common/box.hpp"
#include "particle/common/cluster_membership.hpp"
#include "particle/ed/cluster_index.hpp"
#include "particle/ed/event_queue.hpp"
#include "particle/ed/hierarchical_grid.hpp"

namespace aggkit {

struct EdCounters {
  std::uint64_t merges = 0;              // sticking collisions
  std::uint64_t elastic_collisions = 0;  // collisions with sticking off
  std::uint64_t cell_crossings = 0;      // broad-phase grid crossings of cluster bounding boxes
  std::uint64_t wall_contacts = 0;
  std::uint64_t pair_checks = 0;         // overlap windows of candidate pairs opening or closing
  std::uint64_t stale_events = 0;        // invalidated events popped and skipped
  std::uint64_t events() const { return merges + elastic_collisions + cell_crossings + wall_contacts + pair_checks; }
};

enum class EdStop { time_reached, clusters_reached };

class EventDrivenAggregation {
 public:
  // Largest overlap (1 − |Δx|/2R) any pair may show after an event: contacts are found to round-off of the
  // positions (|x| ≲ L), so this bounds it with a margin for boxes up to L ~ 10^6 R.
  static constexpr double overlap_tolerance = 1e-9;

  // Positions inside the box (reflecting: at least R from every wall), pairwise not overlapping; one velocity
  // per particle. `sticking` false: every collision is elastic (no aggregation). `cells` is the wanted number
  // of finest broad-phase cells (0: about one per particle); cells are never narrower than a contact distance.
  EventDrivenAggregation(const Box& box, double radius, std::span<const Vector3> positions,
                         std::span<const Vector3> velocities, bool sticking = true, std::size_t cells = 0);

  // Elastic collisions (sticking off) until every particle has collided at least `collisions` times (run on
  // the elastic gas, particle/ed/elastic_gas.hpp); then sticking is switched on and the clock restarts at
  // t = 0. Only before any merge (std::logic_error otherwise); std::runtime_error if it cannot finish.
  // `progress`, if given, is called every 2^16 events with the number of particles still short of it.
  void thermalize(std::size_t collisions, const std::function<void(std::size_t pending)>& progress = {});
  // Runs until time t (since the start, or since the end of thermalisation) or until at most
  // `target_clusters` clusters remain (sticking runs only), whichever comes first. `progress`, if given, is
  // called every 2^16 events (it may read time() and clusters()).
  EdStop advance(double t, std::size_t target_clusters = 1, const std::function<void()>& progress = {});
  // Processes the next valid event, whatever its time; false if there is none (for tests and diagnostics).
  bool step();
  // True when no event remains: nothing will ever change again (e.g. clusters at rest relative to each other).
  // Events can be far apart (cluster-level broad phase), so a stretch of time without any proves nothing.
  bool exhausted() { return !skip_stale_events(); }

  double time() const { return double(now_ - clock_origin_); }
  std::size_t particles() const { return offset_.size(); }
  std::size_t clusters() const { return members_.clusters(); }
  const Box& box() const { return box_; }
  double radius() const { return radius_; }
  const EdCounters& counters() const { return counters_; }
  std::size_t queued_events() const { return queue_.size(); }

  double kinetic_energy() const;  // Σ ½ m |v|² over particles (m = 1)
  Vector3 momentum() const;       // Σ m v
  Vector3 wall_impulse() const { return wall_impulse_; }  // momentum given to the walls so far
  Vector3 position(std::uint32_t particle) const;          // unwrapped: contiguous within its cluster
  Vector3 velocity(std::uint32_t particle) const { return velocity_[members_.cluster_of(particle)]; }
  std::vector<Vector3> positions() const;                  // wrapped into the box
  std::vector<Vector3> velocities() const;
  std::vector<std::uint32_t> cluster_labels() const { return members_.labels(); }
  std::vector<std::size_t> cluster_sizes() const;          // index = label of cluster_labels()
  std::uint32_t largest_cluster() const;                   // a cluster id
  std::vector<Vector3> cluster_positions(std::uint32_t cluster) const;  // contiguous (unwrapped)
  std::uint32_t cluster_of(std::uint32_t particle) const { return members_.cluster_of(particle); }
  // max over all pairs of 1 − |Δx|/2R (0 if no pair overlaps); O(N) with a cell list built for the call.
  double largest_overlap() const;

  // Checkpoints (particle/common/checkpoint.hpp): clusters and their members, per-cluster origins, clocks,
  // velocities, boxes and stamps, the broad phase (grid and cluster index), the event queue as it is, the
  // clock and counters. The queue is saved, not rebuilt: predictions made afresh from the restored state
  // would order events of equal times differently and the run would not continue to the same bits.
  // restore() into a run built from the same start continues to the same bits.
  void save(StateWriter& out) const;
  void restore(StateReader& in);

 private:
  struct Contact {
    double time;  // from now
    std::uint32_t a, b;
  };
  Vector3 cluster_origin(std::uint32_t cluster) const;  // origin at time now_
  void bring_to_now(std::uint32_t cluster);
  std::uint64_t new_stamp() { return next_stamp_++; }
  bool valid(const Event& e) const;
  bool skip_stale_events();   // pops invalidated events off the top; false if the queue is then empty
  void execute_next_event();  // pops the (valid) top event, advances the clock to it and processes it
  void process(const Event& e);
  void collide(std::uint32_t i, std::uint32_t j);
  void merge(std::uint32_t i, std::uint32_t j, const Vector3& contact);
  void cross(std::uint32_t cluster, int level, int axis, int face, int direction);
  void check_pair(std::uint32_t x, std::uint32_t y);
  void reflect(std::uint32_t cluster, int axis);
  // Broad phase (ed_broad_phase.cpp).
  Vector3 extent(std::uint32_t cluster) const;  // inflated bounding-box extent
  void register_cluster(std::uint32_t cluster);
  void unregister_cluster(std::uint32_t cluster);
  // The coarsest level a cluster below the top is registered at: its own, or up to the coarsest level where
  // an owner lives (a passenger at a coarser level meets nobody there, and its crossings would be events).
  int passenger_top(std::uint32_t cluster) const;
  // An owner appeared at `level`, coarser than any before: every other cluster below it becomes a passenger
  // up to there, and its crossings are predicted again (the old ones go stale: raises_ changes).
  void raise_populated(int level, std::uint32_t except);
  bool candidates(std::uint32_t x, std::uint32_t y) const;
  // Predictions (ed_prediction.cpp).
  void predict_cluster(std::uint32_t cluster, bool higher_only = false);
  void predict_crossing(std::uint32_t cluster);
  void predict_wall(std::uint32_t cluster);
  void predict_pair(std::uint32_t x, std::uint32_t y);
  Contact first_contact(std::uint32_t x, std::uint32_t y, double horizon);
  void cast(std::uint32_t owner, const Vector3& start, const Vector3& w, double from, double to, std::uint32_t ray,
            Contact& best) const;
  void maybe_compact();

  Box box_;
  double radius_;
  double margin_;  // broad-phase inflation beyond R (round-off guard)
  bool sticking_;
  std::size_t requested_cells_ = 0;  // the constructor's `cells` (kept for the rebuild after thermalize)
  ClusterMembership members_;
  ClusterIndex index_;
  HierarchicalGrid grid_;
  // Per particle: offset from its cluster's origin.
  std::vector<Vector3> offset_;
  // Per cluster (id = a particle id): origin at time clock_, velocity, stamp, extent of the offsets, level.
  std::vector<Vector3> origin_, velocity_, low_, high_;
  std::vector<long double> clock_;
  std::vector<std::uint64_t> stamp_;
  std::vector<int> level_;
  // Live clusters and the top-level ones (candidates of everyone), with positions for O(1) removal.
  std::vector<std::uint32_t> alive_, alive_at_, top_, top_at_;
  std::vector<std::uint32_t> seen_;  // per cluster: epoch of the last candidate enumeration that met it
  std::uint32_t epoch_ = 0;
  struct Ray {
    double begin, end;  // window in which the member can touch the other cluster (from now)
    std::uint32_t particle;
  };
  std::vector<Ray> rays_;  // scratch of first_contact
  // The owner's first member per cell, remembered within one first_contact: the rays of neighbouring members
  // walk overlapping stencils, and each question to the cluster index is a cache miss in a large run. Direct
  // mapped; an entry counts only for the call (`memo_call_`) that wrote it.
  struct MemoCell {
    CellCoords cell{};
    std::uint64_t call = 0;
    std::uint32_t head = 0;
  };
  static constexpr std::size_t memo_size = 1024;
  mutable std::vector<MemoCell> memo_ = std::vector<MemoCell>(memo_size);
  mutable std::uint64_t memo_call_ = 0;
  std::uint32_t first_in_cell(std::uint32_t owner, const CellCoords& cell) const;
  std::uint64_t next_stamp_ = 1;
  EventQueue queue_;
  std::size_t compact_at_ = 0;  // queue size at which stale events are purged (maybe_compact)
  static constexpr std::size_t min_compact = std::size_t(1) << 16;
  int populated_ = 0;          // the coarsest stored level with an owner (clusters below the top)
  std::uint64_t raises_ = 0;   // times populated_ rose; a crossing event carries the count at its prediction
  long double now_ = 0, clock_origin_ = 0;
  Vector3 wall_impulse_{0, 0, 0};
  EdCounters counters_;
};

}  // namespace aggkit

#pragma once
// Contact detection of the time-stepping engine (time_stepping_aggregation.hpp, "Safe times", "Near
// re-check"): the pairs of spheres of different clusters that overlap, or that met during the last flight
// [Degond2024, Sec. 3, step (b)], and the per-sphere safe times of local detection. It owns the 3^d stencil
// table of the cell list and the safe-time state; it reads the spheres, their clusters and the cell list
// of the engine through a SphereView given to each call.
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "particle/common/box.hpp"
#include "particle/common/cell_grid.hpp"
#include "particle/common/cell_list.hpp"
#include "particle/common/cluster_membership.hpp"
#include "particle/common/worker_pool.hpp"

namespace aggkit {

class StateWriter;
class StateReader;
struct TsCounters;

using SpherePairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;  // (lower, higher) sphere

// What a detection pass reads of the engine.
struct SphereView {
  const Box& box;
  double radius;
  const CellGrid& grid;
  const CellList& cells;  // up to date for the spheres examined
  const ClusterMembership& members;
  const std::vector<Vector3>& x;      // per sphere: position (up to date)
  const std::vector<Vector3>& flown;  // per sphere: displacement in the last flight
  const std::vector<double>& speed;   // per cluster id: |V| at the start of the step (empty before the first)
  double longest_flight;              // the largest |flown|
  WorkerPool* pool;                   // null: one thread
};

class ContactDetection {
 public:
  // Relative penetration 1 − |Δx|/2R beyond which two spheres of one cluster are linked (overlaps()).
  static constexpr double same_cluster_tolerance = 1e-2;

  ContactDetection(const CellGrid& grid, std::size_t spheres);

  // Pairs to link: with `among` empty, of different clusters overlapping now (every sphere examined);
  // otherwise those of the given spheres, same-cluster pairs overlapping by more than same_cluster_tolerance
  // included. Sorted, each pair once.
  SpherePairs overlaps(const SphereView& s, std::span<const std::uint32_t> among);
  // The pass after a flight: the pairs of different clusters whose separation came within 2R during it;
  // `local`: the spheres' safe times may be used (nothing but the flights and the clusters changed() names
  // moved the spheres since the last pass). Over the spheres whose safe time ran out when that is allowed,
  // holds and few have, else over every sphere. `fastest`: the largest cluster speed. `safe`: the time from
  // now that every sphere's safe time holds (0 when the pass does not bound it).
  SpherePairs detect(const SphereView& s, bool local, double fastest, double& safe, TsCounters& counters);

  void fly(double dt) { clock_ += dt; }  // the clock of the safe times: the time flown
  // A cluster that absorbed another: its spheres are examined at the next pass.
  void changed(std::uint32_t cluster) { changed_[cluster] = passes_; }
  bool bounds() const { return bounds_; }  // the safe times hold for every sphere
  // A lower bound, from its last examination and those of its neighbours, of the distance from a sphere to
  // the nearest sphere that was then in another cluster, as of the last pass (bounds() only).
  double nearest_bound(std::uint32_t sphere) const { return near_key_[sphere] - rate_[sphere] * clock_; }

  // Checkpoints: the safe-time state and the clock (the stencil table follows from the grid).
  void save(StateWriter& out) const;
  void restore(StateReader& in);

 private:
  struct Spill;
  template <class F>
  void for_stencil(const SphereView& s, std::uint32_t i, F&& f) const;
  double narrowest(const SphereView& s) const;  // the narrowest cell side
  // Pairs to link (overlaps(), or swept after a flight) found sphere by sphere: of the given spheres, or
  // with `among` empty of every sphere.
  SpherePairs search(const SphereView& s, std::span<const std::uint32_t> among, bool swept) const;
  // The contact distance 2R of the safe times, with a margin far above the round-off the positions gather
  // over quiet flights: a gap is a distance less this.
  static double contact_margin(double radius) { return 2.0 * radius * (1.0 + 1e-6); }
  // Every pair once, each cell against itself and the half of its stencil ahead of it; `bound` also sets the
  // per-sphere safe times (swept after a flight).
  SpherePairs half_stencil_pass(const SphereView& s, bool swept, bool bound, double fastest);
  void pass_cells(const SphereView& s, std::size_t from, std::size_t to, bool swept, bool bound, SpherePairs& out,
                  std::vector<Spill>& spill);
  void start_bounds(const SphereView& s, double fastest);
  void finish_bounds(const SphereView& s, const std::vector<std::vector<Spill>>& spills);
  // The local pass over the given spheres (stale_ marks them), each against its whole stencil.
  SpherePairs examine(const SphereView& s, std::span<const std::uint32_t> spheres, double fastest);
  // The spheres whose safe time ran out or whose cluster changed since their examination; `earliest`: the
  // first end among the others.
  std::vector<std::uint32_t> expired(const SphereView& s, double& earliest) const;

  static constexpr std::uint32_t no_cell = 0xffffffffu;
  static constexpr std::size_t parallel_scan = 1024;  // fewer spheres re-checked for contacts: one worker
  static constexpr double local_share = 0.25;  // a local pass when at most this share of the spheres expired
  // The 3^d stencil: first the half of it a pass over every cell takes (the offset 0 and one of each ± pair),
  // then the other half; per cell, its neighbour at each offset (no_cell past a wall).
  std::vector<CellCoords> stencil_;
  std::size_t half_width_ = 0;
  std::vector<std::uint32_t> neighbours_;
  // Per sphere: the clock until which its safe time holds; the rate at which its distance to the spheres of
  // other clusters can shrink (its speed plus the largest, at its examination); near_key_ − rate_ · clock_:
  // a lower bound of that distance now (near re-check), from its examination and from the passes that
  // examined a neighbour since; the pass that examined it. Per cluster id: the pass after which it changed.
  // stale_: scratch of a local pass (the spheres it examines).
  std::vector<double> expires_, near_key_, rate_;
  std::vector<std::uint64_t> checked_pass_, changed_;
  std::vector<char> stale_;
  std::uint64_t passes_ = 0;  // detection passes after flights so far
  double clock_ = 0;          // time flown (the sum of the flights)
  bool bounds_ = false;       // the per-sphere safe times hold for every sphere
};

}  // namespace aggkit

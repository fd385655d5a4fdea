#pragma once
// Time-stepping ballistic aggregation [Degond2024, Sec. 3]: N equal hard discs (2-D) or spheres (3-D) of
// radius R and equal mass; clusters translate rigidly, stick on contact and move on with the
// momentum-weighted velocity [Degond2024, eq. 2.9]. One step of length Δt:
//   1. free flight of every cluster; with reflecting walls a cluster that crosses a wall is reflected as a
//      whole (moved back by twice its penetration, the velocity component reversed, the momentum given to
//      the wall recorded); periodic boxes wrap;
//   2. every pair of different clusters that touched during the flight (overlapping at its end, or whose
//      separation came within 2R on the way) becomes a link and their clusters merge (velocity:
//      mass-weighted mean, so momentum is conserved to round-off);
//   2'. (contact_time, the default) a binary collision — two clusters that met only each other and no wall
//      in the flight — is merged at its contact: both are moved back along their flight to the first
//      touch of the swept pair, merged there, and the merged cluster flies the rest of the flight; its new
//      overlaps, if any, go to step 3 with the other contacts. An isolated collision is then ED's to
//      round-off at any Δt (tests/particle/ts/test_against_ed.cpp); without it every contact is resolved
//      from its end-of-flight overlap and the clusters stay interpenetrated by up to |ΔV| Δt around the
//      link (measured at dt_factor 0.005: N_c 2 % above ED's and P(r) near 2R several standard errors
//      off, bench/results/RESULTS.md);
//   3. the spheres near the new links are moved by the DAHA minimisation (daha.hpp) to a configuration
//      without overlaps in which every link touches; contacts with other clusters that appear during the
//      minimisation (or after a wall correction) become links in turn, and 2–3 repeat until no new link
//      appears [Degond2024, Sec. 3, steps 2c–2e].
// The local almost rigid variant of [Degond2024, Sec. 3.3] is the default: the free spheres of a
// minimisation are those of the merged cluster within Δ_W (interaction_range) of an end of a new link,
// the rest of the cluster is held fixed; links attract only while within Δ_W (eq. 3.30); constraints are
// the same-cluster pairs closer than max(Δ_W, 4R) found from the neighbouring cells of a cell list
// (multipliers per constrained pair: memory O(contacts)). A step's minimisation cost follows the new
// contacts, not N (flight and overlap detection stay O(N) per step). `global` (Sec. 3.1) frees every sphere
// of the clusters touched and constrains all their pairs (O(n²): small systems only).
// Links are the contact graph: the pairs that were linked (new links and every earlier one), stored per
// sphere. Separate clusters are minimised independently, on `threads` workers; results do not depend on
// the thread count.
//
// Substeps: a step in which a cluster would fly farther than substep_displacement · 2R is flown in equal
// substeps that do not, each followed by steps 2–3; contacts are found along the flown paths (a pair whose
// separation came within 2R during the flight), so none is tunnelled through however long the step.
//
// Safe times (local detection): a detection pass gives every sphere it examines its own safe time — its
// gaps to the spheres of other clusters in neighbouring cells, each over the pair's closing speed
// (|V_a| + |V_b|), and for the rest (at least the narrowest cell side apart) that side less 2R over its speed
// plus the largest — and the clock until which it holds. While a sphere's time holds, no pair it is part of
// can touch unless the other sphere's cluster changed (a merge, a minimisation, a wall correction other than
// a specular reflection), and a changed cluster's spheres are examined at the next pass. So after a flight
// only the spheres whose time ran out, and those of changed clusters, are examined (each against its whole
// stencil): the pairs found are those of a pass over every sphere. When more than a quarter have run out,
// or after a wall moved a cluster, every sphere is examined (the half-stencil pass, cheaper per sphere).
//
// Quiet flights: while the flights since a pass that found nothing stay within the earliest end of the
// spheres' safe times, no pair can come within 2R, so those flights skip detection and the cell-list update:
// the result is the same as detecting each flight and finding nothing.
//
// Quiet flights are rigid-body moves: a flight within the safe time is logged (its Δt), not applied to every
// sphere; a cluster's spheres are brought up to date by replaying the logged flights in order with the
// arithmetic of an applied flight (x ← x + Δt V, wrapped on periodic boxes), so the run is the same to the
// bit. A quiet flight then costs O(clusters): each live cluster's extent at its last update, shifted by its
// flight since, is checked against the walls (a margin far above the round-off), and only a cluster that may
// touch one is brought up to date, tested sphere by sphere and reflected as in an applied flight. Everything
// that reads positions (a detection pass, the outputs, checkpoints) brings every cluster up to date first.
//
// Near re-check: a contact-time merge moves the two clusters off the positions the detection pass saw (by
// D = |their displacement|, for most spheres of a large cluster that absorbs a small one a tiny fraction
// of the flight); the spheres that can now touch another cluster are re-checked. An examination records
// the distance to the nearest sphere of another cluster (every pair closer than the narrowest cell side is
// examined); less the closing-speed bound times the time since (and lowered by the examinations of its
// neighbours since, whose clusters may have jumped) it bounds that distance at the pass. A sphere whose
// bound is at least 2R + its own D + the largest D of the flight (and a margin) cannot touch any sphere
// that was then in another cluster, and
// the pairs within one of the merged clusters keep their separations (a rigid shift): re-checking only the
// others finds the same pairs as re-checking every moved sphere, for O(those spheres) instead of
// O(size of the merged cluster) neighbour searches.
//
// Types: the detection passes and their safe times are ContactDetection's (contact_detection.hpp); the
// positions with the logged quiet flights and the clusters' extents are FlightLog's (flight_log.hpp).
//
// Time step: Δt^n = Δt(0) (2 − ln M^n / ln N), Δt(0) = dt_factor · L / max_i |V_i(0)| (L the largest box
// side) [Degond2024, Table 1]: Δt(0) with N clusters, 2Δt(0) with one, growing with ln of the number of
// merges so far (the cluster count falls like a power of t in ballistic aggregation, so the step grows
// steadily through the run rather than all at once at the start).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "analysis/option_rows.hpp"
#include "particle/common/box.hpp"
#include "particle/common/cell_grid.hpp"
#include "particle/common/cell_list.hpp"
#include "particle/common/cluster_membership.hpp"
#include "particle/common/worker_pool.hpp"
#include "particle/ts/contact_detection.hpp"
#include "particle/ts/daha.hpp"
#include "particle/ts/flight_log.hpp"
#include "particle/ts/time_stepping_neighbours.hpp"
#include "particle/ts/worker_ranges.hpp"

namespace aggkit {

struct TsSettings {
  DahaParameters daha;
  double dt_factor = 0.01;         // Δt(0) = dt_factor · L / max|V(0)|
  double interaction_range = 4.0;  // Δ_W / R
  bool global = false;             // Sec. 3.1 instead of the local variant of Sec. 3.3
  std::size_t threads = 1;         // workers for the minimisations of separate clusters
  std::size_t max_rounds = 1000;   // link–minimise rounds per step before giving up (counted)
  bool contact_time = true;        // binary collisions merged at their contact (see the header)
  double substep_displacement = 0.25;  // largest flight of a cluster in one substep, in diameters 2R
  bool quiet_flights = true;       // skip detection within a pass's safe time (see the header); same run
  bool near_recheck = true;        // after contact-time merges re-check only the spheres that can meet
                                   // another cluster (see the header); same run
  bool local_detection = true;     // after a flight examine only the spheres whose safe time ran out (see
                                   // the header); same run
  // InputError for a field outside its option row's range (ts_option_rows), or a damping δ c̄ > 1.
  void validate() const;
};

// The options of the time-stepping engine as a scene and Python give them: key, range, doc and the field
// of TsSettings each sets.
const OptionRows<TsSettings>& ts_option_rows();

struct TsCounters {
  std::uint64_t steps = 0;
  std::uint64_t substeps = 0;           // flights (≥ 1 per step; more when a cluster would fly too far)
  std::uint64_t quiet_flights = 0;      // flights within a safe time (no detection pass needed)
  std::uint64_t rechecked_spheres = 0;  // spheres re-checked after contact-time merges
  std::uint64_t local_passes = 0;       // detection passes over the expired spheres only
  std::uint64_t examined_spheres = 0;   // spheres examined by the detection passes after flights (N per full pass)
  std::uint64_t merges = 0;
  std::uint64_t contact_time_merges = 0;  // binary collisions merged at their contact time
  std::uint64_t secondary_merges = 0;  // merges found after a minimisation of the same step (not in flight)
  std::uint64_t minimisations = 0;
  std::uint64_t minimisation_iterations = 0;
  std::uint64_t iteration_cap_hits = 0;
  std::uint64_t rounds = 0;             // link–minimise rounds (≥ 1 per step with new links)
  std::uint64_t round_cap_hits = 0;
  std::uint64_t wall_contacts = 0;
  std::uint64_t free_spheres = 0;       // summed over minimisations
  double max_overlap = 0;               // largest √φ⁺ of a pair after any minimisation (length units)
  double largest_move = 0;             // largest displacement of a sphere by one minimisation (length units)
  double overlap_sum = 0;               // Σ over minimisations of their final mean link measure (eq. 3.28)
};

enum class TsStop { time_reached, clusters_reached };

class TimeSteppingAggregation {
 public:
  // Relative penetration 1 − |Δx|/2R beyond which two spheres of one cluster that end a minimisation
  // overlapping are linked and minimised again (the constraint lists are built from the positions at the
  // start of a minimisation; a free sphere can move past them).
  static constexpr double same_cluster_tolerance = ContactDetection::same_cluster_tolerance;

  // Positions inside the box (reflecting: at least R from every wall) not overlapping (InputError naming
  // `particles.initial` otherwise); one velocity per particle; at least one nonzero velocity.
  TimeSteppingAggregation(const Box& box, double radius, std::span<const Vector3> positions,
                          std::span<const Vector3> velocities, const TsSettings& settings);

  // One step of length dt (the law's Δt when dt <= 0).
  void step(double dt = 0);
  // Steps until time t (the last step shortened to land on t) or until at most target_clusters remain.
  // `progress` every 256 steps.
  TsStop advance(double t, std::size_t target_clusters, const std::function<void()>& progress = {});
  // True when no cluster moves relative to another (nothing can change any more).
  bool at_rest() const;

  double time() const { return time_; }
  double time_step() const;  // the law's Δt^n now
  double initial_time_step() const { return dt0_; }
  std::size_t particles() const { return flights_.x.size(); }
  std::size_t clusters() const { return members_.clusters(); }
  const Box& box() const { return box_; }
  double radius() const { return radius_; }
  const TsCounters& counters() const { return counters_; }
  const std::vector<Vector3>& positions() const {  // wrapped into the box
    sync_all();
    return flights_.x;
  }
  std::vector<Vector3> velocities() const;
  Vector3 cluster_velocity(std::uint32_t particle) const { return velocity_[members_.cluster_of(particle)]; }
  std::uint32_t cluster_of(std::uint32_t particle) const { return members_.cluster_of(particle); }
  std::vector<std::uint32_t> cluster_labels() const { return members_.labels(); }
  std::vector<Vector3> cluster_positions(std::uint32_t cluster) const;  // unwrapped along the links
  std::uint32_t largest_cluster() const;
  double kinetic_energy() const;  // Σ ½ |v|² (unit masses)
  Vector3 momentum() const;       // Σ v (unit masses)
  Vector3 wall_impulse() const { return wall_impulse_; }
  // The largest √φ⁺ over all pairs, in the DAHA's units (R = 0.2), and the largest 1 − |Δx|/2R.
  double largest_overlap() const;
  double largest_relative_overlap() const;
  // Mean √|φ| over the links of the last minimisation of the last step (0 if none), DAHA units.
  double last_mean_link_measure() const { return last_mean_; }
  double scale() const { return scale_; }  // DAHA units per length unit (0.2 / R)
  std::size_t links() const;

  // Checkpoints (particle/common/checkpoint.hpp): the configuration, clusters, links, cell list, the flight
  // and safe-time state, clock and counters. The DAHA multipliers are not kept: each minimisation starts them
  // afresh [eq. 3.26]. restore() into a run built from the same start and settings continues to the same bits.
  void save(StateWriter& out) const;
  void restore(StateReader& in);

 private:
  struct Group {
    std::uint32_t cluster;
    std::vector<std::uint32_t> seeds;  // ends of new links
  };
  // A binary collision among a flight's contacts: its earliest touching pair and when it touched.
  struct Collision {
    std::uint32_t key;  // the lower cluster
    double tau;         // the fraction of the flight at the first touch
    std::pair<std::uint32_t, std::uint32_t> pair;
  };
  // Moves every sphere (a quiet flight: logs it, header); returns whether the flight needs a detection pass
  // (then every sphere is up to date and the cell list updated).
  bool flight(double dt);
  bool quiet_flight(double dt);  // flight() within the safe time
  void fly_every_sphere(double dt);  // an applied flight, the clusters past a wall reflected
  void sync_all() const { flights_.sync_all(velocity_, members_, pool_.get()); }  // the logged flights replayed
  void refresh_live();  // live_ after merges
  void reflect(std::uint32_t cluster);
  void locate();  // cell list and longest_flight_ from the positions and flights
  double update_speeds();  // speed_ from velocity_ (on the workers); returns the largest
  double fastest() const;  // the largest cluster speed (speed_ of the live clusters)
  SphereView spheres() const;  // what contact detection reads
  void link(std::uint32_t a, std::uint32_t b);
  // Writes only the group's free spheres; `largest_move`: the largest displacement of one of them.
  DahaResult minimise(const Group& group, std::vector<std::uint32_t>& moved, double& largest_move);
  void resolve(SpherePairs new_links);
  // The clusters the new links join, each with the ends of its new links.
  std::vector<Group> groups_of(const SpherePairs& new_links) const;
  // Counts a round's minimisations, wraps their free spheres and moves back a cluster pushed past a wall;
  // returns the spheres to check for new contacts (cell list updated).
  std::vector<std::uint32_t> settle(const std::vector<Group>& groups, const std::vector<DahaResult>& results,
                                    const std::vector<std::vector<std::uint32_t>>& moved, const std::vector<double>& moves);
  // Merges the binary collisions among a flight's contacts at their contact time; returns the other
  // contacts and the overlaps of the merged clusters (for the minimisation).
  SpherePairs merge_binary_contacts(SpherePairs found, double dt);
  // The binary collisions among `found` (the earliest pair of each, in cluster order); the other pairs go
  // to `rest`.
  std::vector<Collision> binary_collisions(const SpherePairs& found, SpherePairs& rest);
  // Moves the merged clusters of `collisions` back to their contact and on with the merged velocity; returns
  // the moved spheres that can now touch another cluster.
  std::vector<std::uint32_t> move_to_contact(const std::vector<Collision>& collisions, double dt);
  // Per merged cluster (`survivor`), its spheres to re-check after the merges moved them at most `farthest`
  // (on `pool`, or on this thread when null).
  std::vector<std::vector<std::uint32_t>> to_recheck(const std::vector<std::uint32_t>& survivor, double farthest,
                                                     WorkerPool* pool) const;
  Vector3 sep(std::uint32_t i, std::uint32_t j) const { return box_.minimum_image(flights_.x[j] - flights_.x[i]); }
  template <class F>
  void for_near(std::uint32_t i, double reach, F&& f) const {  // every j != i within `reach` cells' span
    aggkit::for_near(grid_, cells_, flights_.x, i, reach, std::forward<F>(f));
  }
  std::size_t thread_count() const { return pool_ ? pool_->threads() : 1; }  // threads of the parallel phases
  // f(from, to, worker) over ranges of [0, n) on thread_count() threads (one below ts_parallel_items items).
  template <class F>
  void for_ranges(std::size_t n, F&& f) const {
    aggkit::for_ranges(pool_.get(), n, std::forward<F>(f));
  }

  Box box_;
  double radius_;
  double scale_;
  TsSettings settings_;
  std::unique_ptr<WorkerPool> pool_;  // the `threads` workers, kept between steps (null for one thread)
  CellGrid grid_;
  CellList cells_;
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> movers_;  // scratch of locate: (sphere, new cell) per worker
  ClusterMembership members_;
  // The positions and flights of the spheres with the quiet flights logged: mutable because readers bring
  // them up to date (sync_all), which changes no state a caller can see.
  mutable FlightLog flights_;
  ContactDetection detection_;     // the stencil table and the safe times
  std::vector<Vector3> velocity_;  // per cluster id
  std::vector<std::uint32_t> live_;  // live clusters, increasing (rebuilt by refresh_live after merges)
  bool live_stale_ = true;
  std::vector<char> reflected_;    // per cluster: reflected by a wall in the last flight
  std::vector<std::uint32_t> reflected_list_;  // the clusters reflected_ marks
  std::vector<Vector3> before_;    // scratch of merge_binary_contacts: positions at the pass, then the moves
  std::vector<std::uint32_t> partner_;  // scratch of merge_binary_contacts: per cluster, the one it met (or none/several)
  static constexpr std::size_t parallel_merge = 1024;  // fewer spheres in a flight's merged clusters: one worker
  static constexpr double logged_stretch = 8;  // quiet flights logged when the safe time holds more than this many
  static constexpr std::size_t logged_clusters = 8;  // ... and at most 1/8 as many clusters as spheres remain
  double longest_flight_ = 0;      // the largest |flown|
  std::vector<double> speed_;      // per cluster id: |velocity_|, set at the start of a step
  double safe_left_ = 0;           // time left of the safe time of the last detection pass
  bool jumped_ = false;            // a cluster was moved by a wall other than by a specular reflection
  std::vector<std::vector<std::uint32_t>> links_;  // per sphere: its linked partners
  double time_ = 0, dt0_ = 0;
  Vector3 wall_impulse_{0, 0, 0};
  TsCounters counters_;
  double last_mean_ = 0;
};

}  // namespace aggkit

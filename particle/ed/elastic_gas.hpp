#pragma once
// Event-driven elastic hard discs (2-D) or spheres (3-D) of equal mass: the thermalisation stage of the ED
// aggregation runs ([Gonzalez2011, Sec. 3]: from a square lattice, every particle collides elastically at
// least 10 times, then sticking is switched on) and a reference hard-sphere gas.
//
// Built for throughput (target: 10x the collision rate of a general-purpose event-driven MD code,
// bench/ed_elastic.cpp):
// - one event slot per particle — its earliest predicted collision and its next cell crossing or wall
//   contact — in a tournament tree (particle/common/tournament_tree.hpp), so the queue holds exactly N
//   entries; a collision predicted with a partner whose trajectory has changed since is found stale when
//   it comes up and only that particle is re-predicted [Marin1993];
// - delayed states: a particle's position is stored at the time of its own last event and extrapolated on
//   demand, so an event touches only the particles involved;
// - a cell crossing predicts only against the newly entered layer of cells;
// - the clock is a double offset from a long-double epoch, renormalised every few N events (no time grows
//   large enough to cost precision), and the particle arrays are then re-sorted by cell for locality.
// Exactness: every event is an exact root of the free-flight equations; after any event no pair overlaps
// by more than `overlap_tolerance` of a diameter (tested over whole runs).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "particle/common/box.hpp"

namespace aggkit {

struct ElasticGasCounters {
  std::uint64_t collisions = 0;
  std::uint64_t cell_crossings = 0;
  std::uint64_t wall_contacts = 0;
  std::uint64_t stale_events = 0;  // collisions found invalid when they came up (partner moved on)
  std::uint64_t events() const { return collisions + cell_crossings + wall_contacts + stale_events; }
};

class ElasticGas {
 public:
  static constexpr double overlap_tolerance = 1e-9;

  virtual ~ElasticGas() = default;

  // Runs until time t (since the start).
  virtual void advance(double t) = 0;
  // Runs until every particle has collided at least `collisions` times in total; throws std::runtime_error
  // when that cannot happen (e.g. a particle that never meets another). `progress`, if given, is called every
  // 2^16 events with the number of particles still short of `collisions`.
  virtual void thermalize(std::size_t collisions, const std::function<void(std::size_t pending)>& progress = {}) = 0;
  // Processes the next event (collision, crossing, wall or stale collision); false if there is none.
  virtual bool step() = 0;

  virtual double time() const = 0;
  virtual std::size_t particles() const = 0;
  virtual const ElasticGasCounters& counters() const = 0;
  virtual std::uint32_t collisions_of(std::uint32_t particle) const = 0;
  // In the order of the particles given to make_elastic_gas; positions wrapped into the box.
  virtual std::vector<Vector3> positions() const = 0;
  virtual std::vector<Vector3> velocities() const = 0;
  virtual double kinetic_energy() const = 0;   // Σ ½ |v|² (unit masses)
  virtual Vector3 momentum() const = 0;        // Σ v
  virtual Vector3 wall_impulse() const = 0;    // momentum given to reflecting walls so far
  // Σ over the collisions so far of r_ij · Δp_i = σ |Δv_n| (unit masses; r_ij = x_i − x_j at contact, Δp_i the
  // impulse on i): the collisional virial of the hard-sphere pressure [Allen2017, ch. 2].
  virtual double collision_virial() const = 0;
  // max over all pairs of 1 − |Δx|/2R (0 when none overlaps).
  virtual double largest_overlap() const = 0;
};

// `particles_per_cell` sets the cell size (cells are never narrower than a diameter 2R); 0 picks the default
// measured best in bench/ed_elastic.cpp. Throws InputError for bad radius, counts, overlapping or
// out-of-box positions.
std::unique_ptr<ElasticGas> make_elastic_gas(const Box& box, double radius, std::span<const Vector3> positions,
                                             std::span<const Vector3> velocities, double particles_per_cell = 0);

}  // namespace aggkit

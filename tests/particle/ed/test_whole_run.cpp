// Whole runs checked after every event: no overlaps beyond the stated tolerance, momentum conserved to
// round-off (plus the wall impulse with reflecting walls), kinetic energy never increasing; elastic runs
// conserve energy to round-off.
#include <catch2/catch.hpp>
#include <cmath>

#include "particle/common/initial_state.hpp"
#include "particle/ed/event_driven_aggregation.hpp"

using namespace aggkit;

namespace {

EventDrivenAggregation make_run(int dimension, std::size_t count, double nu, Boundary boundary, VelocityLaw law,
                                bool sticking = true, std::uint64_t seed = 7) {
  const double radius = 0.5;
  const double side = box_side_for_volume_fraction(dimension, count, radius, nu);
  const Box box{dimension, {side, side, dimension == 3 ? side : 0.0}, boundary};
  const auto x = lattice_positions(box, count, radius);
  const auto v = initial_velocities(dimension, count, law, 1.0, seed);
  return EventDrivenAggregation(box, radius, x, v, sticking);
}

double momentum_scale(const EventDrivenAggregation& ed) {
  double s = 0;
  for (const auto& v : ed.velocities()) s += norm(v);
  return s;
}

// Runs to one cluster checking after every event. Round-off: momentum is summed over ≤ N clusters with
// velocities O(1), each merge adds relative error ~1e-16, so 1e-12 of Σ|p| is a generous bound.
void check_whole_run(EventDrivenAggregation ed) {
  const Vector3 p0 = ed.momentum() + ed.wall_impulse();
  const double scale = momentum_scale(ed);
  double energy = ed.kinetic_energy();
  std::size_t events = 0;
  double worst_overlap = 0;
  while (ed.clusters() > 1 && ed.step()) {
    ++events;
    worst_overlap = std::max(worst_overlap, ed.largest_overlap());
    const double e = ed.kinetic_energy();
    REQUIRE(e <= energy * (1 + 1e-13));
    energy = e;
  }
  CHECK(ed.clusters() == 1);
  CHECK(worst_overlap <= EventDrivenAggregation::overlap_tolerance);
  CHECK(norm(ed.momentum() + ed.wall_impulse() - p0) <= 1e-12 * scale);
  CHECK(ed.counters().merges == ed.particles() - 1);
  INFO("events " << events);
}

}  // namespace

TEST_CASE("2-D periodic run to one cluster: no overlap, momentum conserved, energy never grows", "[ed][whole_run]") {
  check_whole_run(make_run(2, 256, 0.1, Boundary::periodic, VelocityLaw::fixed_speed));
}

TEST_CASE("2-D reflecting run to one cluster: momentum plus wall impulse conserved", "[ed][whole_run][walls]") {
  check_whole_run(make_run(2, 225, 0.2, Boundary::reflecting, VelocityLaw::fixed_speed));
}

TEST_CASE("3-D periodic and reflecting runs to one cluster", "[ed][whole_run][3d]") {
  check_whole_run(make_run(3, 125, 0.05, Boundary::periodic, VelocityLaw::uniform_components));
  check_whole_run(make_run(3, 125, 0.1, Boundary::reflecting, VelocityLaw::fixed_speed));
}

TEST_CASE("zero-momentum start keeps zero momentum", "[ed][whole_run]") {
  auto ed = make_run(2, 400, 0.2, Boundary::periodic, VelocityLaw::uniform_components);
  CHECK(norm(ed.momentum()) <= 1e-13 * momentum_scale(ed));
  ed.advance(1e9);
  CHECK(ed.clusters() == 1);
  CHECK(norm(ed.momentum()) <= 1e-12 * 400);
}

TEST_CASE("elastic mode conserves kinetic energy and momentum to round-off", "[ed][elastic]") {
  for (int dimension : {2, 3}) {
    for (Boundary boundary : {Boundary::periodic, Boundary::reflecting}) {
      auto ed = make_run(dimension, dimension == 2 ? 400 : 343, 0.25, boundary, VelocityLaw::fixed_speed, false);
      const double e0 = ed.kinetic_energy();
      const Vector3 p0 = ed.momentum() + ed.wall_impulse();
      const double scale = momentum_scale(ed);
      ed.advance(20.0);
      INFO("dimension " << dimension << ", " << to_string(boundary));
      CHECK(ed.counters().elastic_collisions > 3000);
      CHECK(ed.clusters() == ed.particles());
      // Each collision changes E by ~1e-16 relative; after ~1e4 collisions a random walk gives ~1e-14.
      CHECK(std::abs(ed.kinetic_energy() - e0) <= 1e-12 * e0);
      CHECK(norm(ed.momentum() + ed.wall_impulse() - p0) <= 1e-12 * scale);
      CHECK(ed.largest_overlap() <= EventDrivenAggregation::overlap_tolerance);
    }
  }
}

TEST_CASE("thermalisation: every particle collides enough, then the clock restarts and sticking is on", "[ed][elastic]") {
  auto ed = make_run(2, 100, 0.2, Boundary::periodic, VelocityLaw::fixed_speed);
  const double e0 = ed.kinetic_energy();
  ed.thermalize(5);
  CHECK(ed.counters().elastic_collisions >= 5 * 100 / 2);
  CHECK(ed.counters().merges == 0);
  CHECK(ed.time() == 0.0);
  CHECK(ed.kinetic_energy() == Approx(e0).epsilon(1e-12));
  ed.advance(1e9);
  CHECK(ed.clusters() == 1);
  CHECK(ed.counters().merges == 99);
}

TEST_CASE("progress callbacks of a long advance see the clock run and the clusters fall", "[ed][whole_run]") {
  auto ed = make_run(2, 4000, 0.01, Boundary::periodic, VelocityLaw::fixed_speed);
  std::vector<std::pair<double, std::size_t>> seen;
  REQUIRE(ed.advance(1e9, 1, [&] { seen.emplace_back(ed.time(), ed.clusters()); }) == EdStop::clusters_reached);
  // One call per 2^16 events: ~35 events per particle to one cluster here.
  REQUIRE(seen.size() >= 1);
  CHECK(seen.size() == ed.counters().events() / 65536);  // executed events; stale ones are skipped, not counted
  for (std::size_t k = 1; k < seen.size(); ++k) {
    CHECK(seen[k].first >= seen[k - 1].first);
    CHECK(seen[k].second <= seen[k - 1].second);
  }
  CHECK(seen.back().second > 1);
}

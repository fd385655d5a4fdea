// The fast elastic hard-sphere gas (particle/ed/elastic_gas.hpp): hand-computed collisions, whole runs
// checked after every event (no overlap, energy and momentum conserved to round-off), the trajectory of an
// independent implementation (the ED aggregation engine in elastic mode), thermalisation and bad input.
#include <catch2/catch.hpp>
#include <cmath>
#include <algorithm>
#include <stdexcept>
#include <vector>

#include "analysis/input_error.hpp"
#include "particle/common/initial_state.hpp"
#include "particle/ed/elastic_gas.hpp"
#include "particle/ed/event_driven_aggregation.hpp"

using namespace aggkit;

namespace {

Box cube(int dimension, double side, Boundary boundary) {
  return {dimension, {side, side, dimension == 3 ? side : 0.0}, boundary};
}

struct Start {
  Box box;
  std::vector<Vector3> x, v;
};

Start lattice_start(int dimension, std::size_t count, double nu, Boundary boundary, std::uint64_t seed = 3) {
  const double radius = 0.5;
  const Box box = cube(dimension, box_side_for_volume_fraction(dimension, count, radius, nu), boundary);
  return {box, lattice_positions(box, count, radius),
          initial_velocities(dimension, count, VelocityLaw::fixed_speed, 1.0, seed)};
}

double speed_sum(const std::vector<Vector3>& v) {
  double s = 0;
  for (const auto& u : v) s += norm(u);
  return s;
}

}  // namespace

TEST_CASE("elastic gas: head-on and oblique collisions by hand", "[ed][elastic_gas]") {
  // Head-on, equal masses: the velocities are exchanged at t = (4 − 1)/2 = 1.5.
  {
    const std::vector<Vector3> x{{2, 5, 0}, {6, 5, 0}}, v{{1, 0, 0}, {-1, 0, 0}};
    auto gas = make_elastic_gas(cube(2, 10, Boundary::reflecting), 0.5, x, v);
    gas->advance(1.5 + 0.25);
    CHECK(gas->counters().collisions == 1);
    const auto xs = gas->positions(), vs = gas->velocities();
    CHECK(vs[0][0] == Approx(-1).epsilon(1e-15));
    CHECK(vs[1][0] == Approx(1).epsilon(1e-15));
    CHECK(xs[0][0] == Approx(3.5 - 0.25).epsilon(1e-14));
    CHECK(xs[1][0] == Approx(4.5 + 0.25).epsilon(1e-14));
  }
  // Oblique: (3 − t)² + 0.6² = 1 → t = 2.2, contact normal n = (0.8, 0.6); the moving particle keeps the
  // tangential part (1,0) − 0.8 n and the resting one takes the normal part 0.8 n.
  {
    const std::vector<Vector3> x{{2, 5, 0}, {5, 5.6, 0}}, v{{1, 0, 0}, {0, 0, 0}};
    auto gas = make_elastic_gas(cube(2, 20, Boundary::reflecting), 0.5, x, v);
    gas->advance(2.2);
    CHECK(gas->counters().collisions == 1);
    const auto vs = gas->velocities();
    CHECK(vs[0][0] == Approx(1 - 0.64).epsilon(1e-13));
    CHECK(vs[0][1] == Approx(-0.48).epsilon(1e-13));
    CHECK(vs[1][0] == Approx(0.64).epsilon(1e-13));
    CHECK(vs[1][1] == Approx(0.48).epsilon(1e-13));
  }
  // Periodic face: the pair is 1.5 + 1.5 apart across x = 0 and meets at t = (3 − 1)/2 = 1.
  {
    const std::vector<Vector3> x{{1.5, 3, 0}, {7.5, 3, 0}}, v{{-1, 0, 0}, {1, 0, 0}};
    auto gas = make_elastic_gas(cube(2, 9, Boundary::periodic), 0.5, x, v);
    gas->advance(1 - 1e-9);
    CHECK(gas->counters().collisions == 0);
    gas->advance(1 + 1e-9);
    CHECK(gas->counters().collisions == 1);
  }
  // Wall: a particle at 1 moving at −1 reaches the wall (x = R) at t = 0.5 and comes back.
  {
    const std::vector<Vector3> x{{1, 1, 1}}, v{{-1, 0, 0}};
    auto gas = make_elastic_gas(cube(3, 4, Boundary::reflecting), 0.5, x, v);
    gas->advance(2.0);
    CHECK(gas->counters().wall_contacts == 1);
    CHECK(gas->positions()[0][0] == Approx(2.0).epsilon(1e-14));
    CHECK(gas->wall_impulse()[0] == Approx(-2.0).epsilon(1e-15));
  }
}

// Whole runs checked after every event. Energy: each collision changes Σ|v|² by O(1e-16) relative, so
// 1e-12 bounds ~1e4 collisions; the overlap tolerance is the engine's stated one.
TEST_CASE("elastic gas: every event leaves no overlap and conserves energy and momentum", "[ed][elastic_gas]") {
  for (int dimension : {2, 3}) {
    for (Boundary boundary : {Boundary::periodic, Boundary::reflecting}) {
      for (double nu : {0.05, 0.3}) {
        const Start s = lattice_start(dimension, dimension == 2 ? 400 : 343, nu, boundary);
        auto gas = make_elastic_gas(s.box, 0.5, s.x, s.v, dimension == 2 ? 1.0 : 0.5);
        const double e0 = gas->kinetic_energy();
        const Vector3 p0 = gas->momentum();
        const double scale = speed_sum(s.v);
        double worst = 0;
        while (gas->counters().collisions < 4000 && gas->step()) worst = std::max(worst, gas->largest_overlap());
        INFO("dimension " << dimension << " " << to_string(boundary) << " nu " << nu);
        CHECK(worst <= ElasticGas::overlap_tolerance);
        CHECK(std::abs(gas->kinetic_energy() - e0) <= 1e-12 * e0);
        CHECK(norm(gas->momentum() + gas->wall_impulse() - p0) <= 1e-12 * scale);
      }
    }
  }
}

// Independent implementation: the ED aggregation engine with sticking off (a heap of all predictions,
// particle-level cells of another size) must follow the same trajectory. Hard-sphere dynamics amplify
// round-off differences by ~ (mean free path / diameter) per collision, so the comparison runs for about
// four collisions per particle; measured differences are up to 1.3e-10 (they reach 1e-8 at 6 per particle),
// the tolerance 1e-8 leaves two orders for that growth while any wrong collision (an O(1) change) fails it.
TEST_CASE("elastic gas follows the trajectory of the ED engine in elastic mode", "[ed][elastic_gas]") {
  for (int dimension : {2, 3}) {
    for (Boundary boundary : {Boundary::periodic, Boundary::reflecting}) {
      const Start s = lattice_start(dimension, dimension == 2 ? 300 : 216, 0.15, boundary, 11);
      auto gas = make_elastic_gas(s.box, 0.5, s.x, s.v);
      EventDrivenAggregation ed(s.box, 0.5, s.x, s.v, false);
      const double t = dimension == 2 ? 6.0 : 4.0;
      gas->advance(t);
      ed.advance(t);
      INFO("dimension " << dimension << " " << to_string(boundary));
      REQUIRE(gas->counters().collisions == ed.counters().elastic_collisions);
      CHECK(gas->counters().collisions > 3 * s.x.size() / 2);  // more than 3 collisions per particle on average
      const auto xg = gas->positions(), vg = gas->velocities(), xe = ed.positions(), ve = ed.velocities();
      double dx = 0, dv = 0;
      for (std::size_t p = 0; p < xg.size(); ++p) {
        dx = std::max(dx, norm(s.box.minimum_image(xg[p] - xe[p])));
        dv = std::max(dv, norm(vg[p] - ve[p]));
      }
      CHECK(dx < 1e-8);
      CHECK(dv < 1e-8);
    }
  }
}

TEST_CASE("elastic gas: thermalisation gives every particle its collisions", "[ed][elastic_gas]") {
  const Start s = lattice_start(2, 500, 0.2, Boundary::reflecting);
  auto gas = make_elastic_gas(s.box, 0.5, s.x, s.v);
  gas->thermalize(10);
  std::uint32_t fewest = 1u << 30;
  for (std::uint32_t p = 0; p < 500; ++p) fewest = std::min(fewest, gas->collisions_of(p));
  CHECK(fewest >= 10);
  CHECK(gas->largest_overlap() <= ElasticGas::overlap_tolerance);
  // The positions handed on are inside the box, at least R from the walls (a sticking run can start there).
  for (const auto& x : gas->positions())
    for (int d = 0; d < 2; ++d) CHECK((x[d] >= 0.5 && x[d] <= s.box.side[d] - 0.5));
  // Continuing after the thermalisation keeps counting.
  const auto before = gas->counters().collisions;
  gas->advance(gas->time() + 5.0);
  CHECK(gas->counters().collisions > before);

  // Progress: called every 2^16 events with the particles still short, which never grows and ends at 0
  // particles short only when the stage is done (500 particles × 300 collisions: ~3e5 events).
  std::vector<std::size_t> pending;
  gas->thermalize(300, [&](std::size_t left) { pending.push_back(left); });
  REQUIRE(pending.size() >= 2);
  CHECK(pending.front() <= 500);
  CHECK(std::is_sorted(pending.rbegin(), pending.rend()));
  for (std::uint32_t p = 0; p < 500; ++p) CHECK(gas->collisions_of(p) >= 300);

  // A lone particle never collides: the thermalisation says so instead of running forever.
  const std::vector<Vector3> x{{2, 2, 0}}, v{{1, 0.3, 0}};
  auto lone = make_elastic_gas(cube(2, 10, Boundary::reflecting), 0.5, x, v);
  CHECK_THROWS_AS(lone->thermalize(1), std::runtime_error);
}

TEST_CASE("elastic gas: the clock renormalisation is invisible in long runs", "[ed][elastic_gas]") {
  // 100 particles: the clock is renormalised and the particles re-sorted every 8 N + 1e5 events, i.e.
  // several times here; energy, momentum and overlaps are checked at the end.
  const Start s = lattice_start(2, 100, 0.1, Boundary::periodic);
  auto gas = make_elastic_gas(s.box, 0.5, s.x, s.v);
  const double e0 = gas->kinetic_energy();
  gas->advance(30000.0);
  CHECK(gas->counters().events() > 400000);
  CHECK(gas->time() == Approx(30000.0).epsilon(1e-15));
  CHECK(std::abs(gas->kinetic_energy() - e0) <= 1e-11 * e0);
  CHECK(gas->largest_overlap() <= ElasticGas::overlap_tolerance);
}

TEST_CASE("elastic gas: particles keep their identity through the re-sorting", "[ed][elastic_gas]") {
  // All particles move with one velocity, so none ever collides and each position is known exactly:
  // x(t) = x(0) + v t (mod L). Over t = 6e4 the run passes >4e5 cell crossings and so several
  // renormalisations with re-sorting; round-off grows by ~1e-16 L per event, hence the 1e-8 tolerance.
  const Start s = lattice_start(2, 49, 0.05, Boundary::periodic);
  const std::vector<Vector3> v(49, Vector3{1.0, 0.37, 0.0});
  auto gas = make_elastic_gas(s.box, 0.5, s.x, v, 0.25);
  const double t = 6e4;
  gas->advance(t);
  CHECK(gas->counters().cell_crossings > 400000);  // four renormalisations at least
  CHECK(gas->counters().collisions == 0);
  const auto x = gas->positions();
  for (std::size_t p = 0; p < x.size(); ++p) {
    const Vector3 expected = s.box.wrap(s.x[p] + t * v[p]);
    CHECK(norm(s.box.minimum_image(x[p] - expected)) < 1e-8);
  }
}

TEST_CASE("elastic gas: a crowded cell grows the cell table", "[ed][elastic_gas]") {
  // Cells of side 200/6 = 33.3 (36 particles in 36 cells), tables of 16 entries. Group A
  // (12 discs, moving +x) catches up with the cell of group B (12 discs at rest, other rows of the same
  // cell row), so one cell must hold 24: the table grows. Nothing collides; every position stays exact.
  std::vector<Vector3> x, v;
  for (int k = 0; k < 12; ++k) {
    x.push_back({2.0 + 1.5 * (k % 4), 2.0 + 1.5 * (k / 4), 0});
    v.push_back({1.0, 0.0, 0.0});
  }
  for (int k = 0; k < 12; ++k) {
    x.push_back({70.0 + 1.5 * (k % 4), 20.0 + 1.5 * (k / 4), 0});
    v.push_back({0.0, 0.0, 0.0});
  }
  for (int k = 0; k < 12; ++k) {  // the rest of the gas, at rest in other cell rows
    x.push_back({10.0 + 15.0 * k, 120.0, 0});
    v.push_back({0.0, 0.0, 0.0});
  }
  const Box box = cube(2, 200, Boundary::periodic);
  auto gas = make_elastic_gas(box, 0.5, x, v, 0.9);  // side sqrt(200² · 0.9 / 36) = 31.6 → 6 cells per axis
  gas->advance(70.0);  // group A now spans x in [72, 78.5]: inside B's cell (x in [66.7, 100))
  CHECK(gas->counters().collisions == 0);
  CHECK(gas->largest_overlap() <= ElasticGas::overlap_tolerance);
  const auto xs = gas->positions();
  for (std::size_t p = 0; p < x.size(); ++p)
    CHECK(norm(box.minimum_image(xs[p] - box.wrap(x[p] + 70.0 * v[p]))) < 1e-10);
}

TEST_CASE("elastic gas: bad input is named", "[ed][elastic_gas]") {
  const std::vector<Vector3> x{{2, 2, 0}, {2.5, 2, 0}}, v{{0, 0, 0}, {0, 0, 0}};
  CHECK_THROWS_AS(make_elastic_gas(cube(2, 10, Boundary::periodic), 0.5, x, v), InputError);  // overlapping
  CHECK_THROWS_AS(make_elastic_gas(cube(2, 10, Boundary::periodic), -1.0, x, v), InputError);
  CHECK_THROWS_AS(make_elastic_gas(cube(2, 2, Boundary::periodic), 0.5, {x.data(), 1}, {v.data(), 1}), InputError);
  const std::vector<Vector3> outside{{0.2, 2, 0}};
  CHECK_THROWS_AS(make_elastic_gas(cube(2, 10, Boundary::reflecting), 0.5, outside, {v.data(), 1}), InputError);
}

// The cluster-level engine (hierarchical-grid broad phase, ray-cast narrow phase) against an independent
// brute-force oracle: every particle pair of different clusters over all nearby periodic images, every
// cluster against every wall, all positions advanced at each event. Small random systems must give the same
// merge times (to 1e-9, round-off of the two clocks) and the same final velocity.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "particle/common/initial_state.hpp"
#include "particle/ed/collision_time.hpp"
#include "particle/ed/event_driven_aggregation.hpp"

using namespace aggkit;

namespace {

struct BruteForce {
  Box box;
  double radius;
  std::vector<Vector3> x, v;
  std::vector<int> label;
  double t = 0;

  std::size_t clusters() const {
    std::vector<int> l = label;
    std::sort(l.begin(), l.end());
    return std::size_t(std::unique(l.begin(), l.end()) - l.begin());
  }
  void set_velocity(int cluster, const Vector3& u) {
    for (std::size_t p = 0; p < x.size(); ++p)
      if (label[p] == cluster) v[p] = u;
  }
  // Advances to the next merge; walls in between reverse whole clusters.
  void next_merge() {
    constexpr double never = std::numeric_limits<double>::infinity();
    const int reach = box.boundary == Boundary::periodic ? 1 : 0;
    while (true) {
      double best = never;
      int kind = 0, i_best = 0, j_best = 0, axis_best = 0;
      for (std::size_t i = 0; i < x.size(); ++i)
        for (std::size_t j = i + 1; j < x.size(); ++j) {
          if (label[i] == label[j]) continue;
          for (int kx = -reach; kx <= reach; ++kx)
            for (int ky = -reach; ky <= reach; ++ky)
              for (int kz = box.dimension == 3 ? -reach : 0; kz <= (box.dimension == 3 ? reach : 0); ++kz) {
                const Vector3 image{kx * box.side[0], ky * box.side[1], kz * box.side[2]};
                const double tc = collision_time(box.minimum_image(x[j] - x[i]) + image, v[j] - v[i], 2 * radius);
                if (tc < best) best = tc, kind = 0, i_best = int(i), j_best = int(j);
              }
        }
      if (box.boundary == Boundary::reflecting)
        for (std::size_t p = 0; p < x.size(); ++p)
          for (int a = 0; a < box.dimension; ++a) {
            double tw = never;
            if (v[p][a] > 0) tw = std::max(0.0, box.side[a] - radius - x[p][a]) / v[p][a];
            if (v[p][a] < 0) tw = std::max(0.0, x[p][a] - radius) / -v[p][a];
            if (tw < best) best = tw, kind = 1, i_best = int(p), axis_best = a;
          }
      // Images within one period of the minimum image hold every contact before the relative displacement
      // reaches L/4: no event by then, move on and look again.
      double fastest = 0;
      for (const auto& u : v) fastest = std::max(fastest, norm(u));
      REQUIRE(fastest > 0);
      const double horizon = 0.25 * std::min(box.side[0], box.side[1]) / (2 * fastest);
      if (best > horizon) kind = 2, best = horizon;
      for (std::size_t p = 0; p < x.size(); ++p) x[p] = x[p] + best * v[p];
      t += best;
      if (kind == 2) continue;
      if (kind == 1) {
        Vector3 u = v[i_best];
        u[axis_best] = -u[axis_best];
        set_velocity(label[i_best], u);
        continue;
      }
      const int a = label[i_best], b = label[j_best];
      double ma = 0, mb = 0;
      for (int l : label) ma += l == a, mb += l == b;
      const Vector3 u = (1.0 / (ma + mb)) * (ma * v[i_best] + mb * v[j_best]);
      for (int& l : label)
        if (l == b) l = a;
      set_velocity(a, u);
      return;
    }
  }
};

void compare(int dimension, Boundary boundary, std::size_t count, double nu, std::uint64_t seed) {
  const double radius = 0.5;
  const double side = box_side_for_volume_fraction(dimension, count, radius, nu);
  const Box box{dimension, {side, side, dimension == 3 ? side : 0.0}, boundary};
  const auto x = lattice_positions(box, count, radius);
  const auto v = initial_velocities(dimension, count, VelocityLaw::fixed_speed, 1.0, seed);
  EventDrivenAggregation ed(box, radius, x, v, true, /*cells=*/4 * count);  // several grid levels even here
  BruteForce oracle{box, radius, x, v, {}};
  for (std::size_t p = 0; p < count; ++p) oracle.label.push_back(int(p));
  INFO("dimension " << dimension << ", " << to_string(boundary) << ", seed " << seed);
  for (std::size_t target = count - 1; target >= 1; --target) {
    oracle.next_merge();
    REQUIRE(ed.advance(1e9, target) == EdStop::clusters_reached);
    INFO("merge " << count - target);
    REQUIRE(ed.time() == Approx(oracle.t).epsilon(1e-9));
  }
  for (int a = 0; a < 3; ++a) CHECK(ed.velocity(0)[a] == Approx(oracle.v[0][a]).margin(1e-9));
}

}  // namespace

TEST_CASE("cluster-level engine reproduces a brute-force oracle merge by merge", "[ed][oracle]") {
  for (std::uint64_t seed : {1u, 2u, 3u, 4u, 5u}) {
    compare(2, Boundary::periodic, 40, 0.05, seed);
    compare(2, Boundary::reflecting, 40, 0.1, seed);
    compare(3, Boundary::periodic, 27, 0.05, seed);
    compare(3, Boundary::reflecting, 27, 0.1, seed);
  }
  // Dilute: clusters grow wider than half the box (top level, minimum images) before the last merges.
  for (std::uint64_t seed : {6u, 7u, 8u}) compare(2, Boundary::periodic, 60, 0.01, seed);
}

#include "particle/dem/gravity_tree.hpp"

#include <algorithm>
#include <atomic>
#include <array>
#include <cmath>
#include <cstdint>
#include <thread>

namespace aggkit {

namespace {

constexpr std::size_t leaf_size = 8;

struct Cell {
  Vector3 centre{0, 0, 0};  // centre of mass
  Vector3 lo{0, 0, 0};      // lower corner of the cube
  double mass = 0, side = 0;
  std::array<double, 6> q{};  // Q_xx, Q_yy, Q_zz, Q_xy, Q_xz, Q_yz
  std::uint32_t begin = 0, end = 0;  // particles order[begin, end)
  std::int32_t child[8];
  bool leaf = true;
};

class Tree {
 public:
  Tree(const std::vector<Vector3>& x, const std::vector<double>& m) : x_(x), m_(m), order_(x.size()) {
    for (std::uint32_t i = 0; i < order_.size(); ++i) order_[i] = i;
    Vector3 lo = x[0], hi = x[0];
    for (const Vector3& p : x)
      for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], p[d]), hi[d] = std::max(hi[d], p[d]);
    double side = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    side = side > 0 ? side * (1 + 1e-12) : 1.0;
    cells_.reserve(2 * x.size() / leaf_size + 16);
    build(0, std::uint32_t(x.size()), lo, side, 0);
  }

  Vector3 acceleration_on(std::size_t i, double G, double eps2, double theta) const {
    double a[3] = {0, 0, 0};
    walk(0, i, G, eps2, theta * theta, a);
    return {a[0], a[1], a[2]};
  }

 private:
  std::int32_t build(std::uint32_t begin, std::uint32_t end, const Vector3& lo, double side, int depth) {
    const std::int32_t index = std::int32_t(cells_.size());
    cells_.emplace_back();
    Cell cell;
    cell.begin = begin, cell.end = end, cell.side = side, cell.lo = lo;
    for (std::uint32_t k = begin; k < end; ++k) {
      const std::uint32_t i = order_[k];
      cell.mass += m_[i];
      cell.centre = cell.centre + m_[i] * x_[i];
    }
    cell.centre = (1 / cell.mass) * cell.centre;
    for (std::uint32_t k = begin; k < end; ++k) {
      const std::uint32_t i = order_[k];
      const Vector3 y = x_[i] - cell.centre;
      const double y2 = dot(y, y);
      cell.q[0] += m_[i] * (3 * y[0] * y[0] - y2);
      cell.q[1] += m_[i] * (3 * y[1] * y[1] - y2);
      cell.q[2] += m_[i] * (3 * y[2] * y[2] - y2);
      cell.q[3] += m_[i] * 3 * y[0] * y[1];
      cell.q[4] += m_[i] * 3 * y[0] * y[2];
      cell.q[5] += m_[i] * 3 * y[1] * y[2];
    }
    std::fill(std::begin(cell.child), std::end(cell.child), -1);
    if (end - begin > leaf_size && depth < 60) {
      cell.leaf = false;
      const double half = 0.5 * side;
      const Vector3 mid{lo[0] + half, lo[1] + half, lo[2] + half};
      auto octant = [&](std::uint32_t i) {
        return (x_[i][0] >= mid[0] ? 1 : 0) | (x_[i][1] >= mid[1] ? 2 : 0) | (x_[i][2] >= mid[2] ? 4 : 0);
      };
      // Stable partition into the eight octants.
      std::array<std::uint32_t, 9> start{};
      for (std::uint32_t k = begin; k < end; ++k) ++start[octant(order_[k]) + 1];
      for (int o = 0; o < 8; ++o) start[o + 1] += start[o];
      std::vector<std::uint32_t> sorted(end - begin);
      std::array<std::uint32_t, 8> fill{};
      for (int o = 0; o < 8; ++o) fill[o] = start[o];
      for (std::uint32_t k = begin; k < end; ++k) sorted[fill[octant(order_[k])]++] = order_[k];
      std::copy(sorted.begin(), sorted.end(), order_.begin() + begin);
      for (int o = 0; o < 8; ++o) {
        if (start[o] == start[o + 1]) continue;
        const Vector3 child_lo{lo[0] + ((o & 1) ? half : 0), lo[1] + ((o & 2) ? half : 0), lo[2] + ((o & 4) ? half : 0)};
        cell.child[o] = build(begin + start[o], begin + start[o + 1], child_lo, half, depth + 1);
      }
    }
    cells_[std::size_t(index)] = cell;
    return index;
  }

  void walk(std::int32_t index, std::size_t i, double G, double eps2, double theta2, double* a) const {
    const Cell& c = cells_[std::size_t(index)];
    const double d[3] = {x_[i][0] - c.centre[0], x_[i][1] - c.centre[1], x_[i][2] - c.centre[2]};
    const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    // Accept when l < θ r; a cell holding i is never accepted (its particles are summed or opened).
    bool holds_i = true;
    for (int k = 0; k < 3; ++k) holds_i = holds_i && x_[i][k] >= c.lo[k] && x_[i][k] <= c.lo[k] + c.side;
    if (!holds_i && c.side * c.side < theta2 * r2) {
      const double r = std::sqrt(r2), inv2 = 1 / r2, inv3 = inv2 / r, inv5 = inv3 * inv2, inv7 = inv5 * inv2;
      const double qd[3] = {c.q[0] * d[0] + c.q[3] * d[1] + c.q[4] * d[2], c.q[3] * d[0] + c.q[1] * d[1] + c.q[5] * d[2],
                            c.q[4] * d[0] + c.q[5] * d[1] + c.q[2] * d[2]};
      const double dqd = d[0] * qd[0] + d[1] * qd[1] + d[2] * qd[2];
      for (int k = 0; k < 3; ++k) a[k] += G * (-c.mass * d[k] * inv3 + qd[k] * inv5 - 2.5 * dqd * d[k] * inv7);
      return;
    }
    if (c.leaf) {
      for (std::uint32_t k = c.begin; k < c.end; ++k) {
        const std::uint32_t j = order_[k];
        if (j == i) continue;
        const double e[3] = {x_[j][0] - x_[i][0], x_[j][1] - x_[i][1], x_[j][2] - x_[i][2]};
        const double s2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
        const double s = std::sqrt(s2);
        const double f = s > 0 ? G * m_[j] / (s * (s2 + eps2)) : 0.0;
        a[0] += f * e[0], a[1] += f * e[1], a[2] += f * e[2];
      }
      return;
    }
    for (std::int32_t child : c.child)
      if (child >= 0) walk(child, i, G, eps2, theta2, a);
  }

  const std::vector<Vector3>& x_;
  const std::vector<double>& m_;
  std::vector<std::uint32_t> order_;
  std::vector<Cell> cells_;
};

}  // namespace

void tree_gravity(const std::vector<Vector3>& x, const std::vector<double>& m, double G, double softening, double theta,
                  std::size_t threads, std::vector<Vector3>& force) {
  if (x.size() < 2) return;
  const Tree tree(x, m);
  const double eps2 = softening * softening;
  auto run = [&](std::size_t i) { force[i] = force[i] + m[i] * tree.acceleration_on(i, G, eps2, theta); };
  threads = std::max<std::size_t>(1, std::min(threads, x.size() / 256 + 1));
  if (threads == 1) {
    for (std::size_t i = 0; i < x.size(); ++i) run(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::vector<std::thread> pool;
  for (std::size_t w = 0; w < threads; ++w)
    pool.emplace_back([&] {
      for (std::size_t b = next.fetch_add(256); b < x.size(); b = next.fetch_add(256))
        for (std::size_t i = b; i < std::min(x.size(), b + 256); ++i) run(i);
    });
  for (std::thread& t : pool) t.join();
}

}  // namespace aggkit

#include "particle/dem/gravity_tree.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "particle/common/simd_clones.hpp"

namespace aggkit {

namespace {

constexpr std::size_t leaf_size = 16;
constexpr std::uint32_t group_size = 64;  // particles sharing one walk (leaves 16, groups 64: measured best of 4–16 and 16–64, bench/results/RESULTS.md)

// Interaction lists of one group walk: accepted cells (centre of mass, mass, quadrupole) and the particles
// of opened leaves, as arrays.
struct Scratch {
  std::vector<double> cx, cy, cz, mass, dx, dy, dz, dm;
  std::array<std::vector<double>, 6> q;
  std::vector<double> mx, my, mz, ax, ay, az;  // the group's members: positions, accelerations / G
  void members(std::size_t n) {
    for (auto* v : {&mx, &my, &mz, &ax, &ay, &az}) v->resize(n);
  }
  void clear() {
    for (auto* v : {&cx, &cy, &cz, &mass, &dx, &dy, &dz, &dm}) v->clear();
    for (auto& v : q) v.clear();
  }
};

// The lists' accelerations / G on each member, by vectorised loops over the accepted cells (monopole and
// quadrupole) and the leaves' particles (the engine's softened law).
AGGKIT_SIMD_CLONES void evaluate_lists(Scratch& s, std::size_t members, double eps2) {
  const std::size_t nm = s.mass.size(), nd = s.dm.size();
  const double* cx = s.cx.data(); const double* cy = s.cy.data(); const double* cz = s.cz.data();
  const double* cm = s.mass.data();
  const double *q0 = s.q[0].data(), *q1 = s.q[1].data(), *q2 = s.q[2].data(), *q3 = s.q[3].data(), *q4 = s.q[4].data(),
               *q5 = s.q[5].data();
  const double* px = s.dx.data(); const double* py = s.dy.data(); const double* pz = s.dz.data();
  const double* pm = s.dm.data();
  for (std::size_t k = 0; k < members; ++k) {
    const double xi = s.mx[k], yi = s.my[k], zi = s.mz[k];
    double ax = 0, ay = 0, az = 0;
#pragma omp simd reduction(+ : ax, ay, az)
    for (std::size_t c = 0; c < nm; ++c) {
      const double dx = xi - cx[c], dy = yi - cy[c], dz = zi - cz[c];
      const double r2 = dx * dx + dy * dy + dz * dz;
      const double inv2 = 1 / r2, inv = std::sqrt(inv2), inv3 = inv2 * inv, inv5 = inv3 * inv2, inv7 = inv5 * inv2;
      const double qx = q0[c] * dx + q3[c] * dy + q4[c] * dz, qy = q3[c] * dx + q1[c] * dy + q5[c] * dz,
                   qz = q4[c] * dx + q5[c] * dy + q2[c] * dz;
      const double dqd = dx * qx + dy * qy + dz * qz;
      const double radial = -cm[c] * inv3 - 2.5 * dqd * inv7;
      ax += radial * dx + qx * inv5, ay += radial * dy + qy * inv5, az += radial * dz + qz * inv5;
    }
#pragma omp simd reduction(+ : ax, ay, az)
    for (std::size_t j = 0; j < nd; ++j) {
      const double ex = px[j] - xi, ey = py[j] - yi, ez = pz[j] - zi;
      const double s2 = ex * ex + ey * ey + ez * ez;
      // itself (s = 0) adds nothing; branch-free, so that the loop vectorises
      const double f = (s2 > 0 ? pm[j] : 0.0) / (s2 > 0 ? std::sqrt(s2) * (s2 + eps2) : 1.0);
      ax += f * ex, ay += f * ey, az += f * ez;
    }
    s.ax[k] = ax, s.ay[k] = ay, s.az[k] = az;
  }
}

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

  // The groups of the walk: the cells of at most group_size particles whose parent holds more (a leaf of
  // the whole tree if it has fewer), in tree order.
  std::vector<std::int32_t> groups() const {
    std::vector<std::int32_t> out;
    collect_groups(0, out);
    return out;
  }

  // Accelerations of the group's particles (added to a[order position]) from one walk for the whole group
  // [Barnes1990]: a cell is accepted when l < θ d with d the distance from its centre of mass to the group's
  // bounding box and the cell does not overlap that box (so it holds none of the group's particles), which
  // is stricter than each member's own criterion; otherwise opened, and a leaf's particles are summed pair
  // by pair. The lists are then evaluated for every member with vectorised loops.
  void group_accelerations(std::int32_t group, double G, double eps2, double theta, Scratch& s, std::vector<Vector3>& a) const {
    const Cell& g = cells_[std::size_t(group)];
    Vector3 lo = x_[order_[g.begin]], hi = lo;
    for (std::uint32_t k = g.begin; k < g.end; ++k)
      for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], x_[order_[k]][d]), hi[d] = std::max(hi[d], x_[order_[k]][d]);
    s.clear();
    gather(0, lo, hi, theta * theta, s);
    s.members(g.end - g.begin);
    for (std::uint32_t k = g.begin; k < g.end; ++k) {
      const Vector3& p = x_[order_[k]];
      s.mx[k - g.begin] = p[0], s.my[k - g.begin] = p[1], s.mz[k - g.begin] = p[2];
    }
    evaluate_lists(s, g.end - g.begin, eps2);
    for (std::uint32_t k = g.begin; k < g.end; ++k) a[k] = {G * s.ax[k - g.begin], G * s.ay[k - g.begin], G * s.az[k - g.begin]};
  }

  std::uint32_t particle_at(std::uint32_t k) const { return order_[k]; }

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

  void collect_groups(std::int32_t index, std::vector<std::int32_t>& out) const {
    const Cell& c = cells_[std::size_t(index)];
    if (c.leaf || c.end - c.begin <= group_size) {
      out.push_back(index);
      return;
    }
    for (std::int32_t child : c.child)
      if (child >= 0) collect_groups(child, out);
  }

  void gather(std::int32_t index, const Vector3& lo, const Vector3& hi, double theta2, Scratch& s) const {
    const Cell& c = cells_[std::size_t(index)];
    double d2 = 0;  // squared distance from the centre of mass to the group's box
    bool overlaps = true;
    for (int k = 0; k < 3; ++k) {
      const double below = lo[k] - c.centre[k], above = c.centre[k] - hi[k];
      const double gap = std::max({below, above, 0.0});
      d2 += gap * gap;
      overlaps = overlaps && c.lo[k] <= hi[k] && c.lo[k] + c.side >= lo[k];
    }
    if (!overlaps && c.side * c.side < theta2 * d2) {
      s.cx.push_back(c.centre[0]), s.cy.push_back(c.centre[1]), s.cz.push_back(c.centre[2]), s.mass.push_back(c.mass);
      for (int k = 0; k < 6; ++k) s.q[k].push_back(c.q[k]);
      return;
    }
    if (c.leaf) {
      for (std::uint32_t k = c.begin; k < c.end; ++k) {
        const std::uint32_t j = order_[k];
        s.dx.push_back(x_[j][0]), s.dy.push_back(x_[j][1]), s.dz.push_back(x_[j][2]), s.dm.push_back(m_[j]);
      }
      return;
    }
    for (std::int32_t child : c.child)
      if (child >= 0) gather(child, lo, hi, theta2, s);
  }

  const std::vector<Vector3>& x_;
  const std::vector<double>& m_;
  std::vector<std::uint32_t> order_;
  std::vector<Cell> cells_;
};

}  // namespace

void tree_gravity(const std::vector<Vector3>& x, const std::vector<double>& m, double G, double softening, double theta,
                  WorkerPool* pool, std::vector<Vector3>& force) {
  if (x.size() < 2) return;
  const Tree tree(x, m);
  const double eps2 = softening * softening;
  const std::vector<std::int32_t> groups = tree.groups();
  std::vector<Vector3> a(x.size());  // by tree order
  // Jobs of 16 groups; each thread keeps its lists' storage from job to job.
  constexpr std::size_t per_job = 16;
  const std::size_t jobs = (groups.size() + per_job - 1) / per_job;
  auto run = [&](std::size_t job) {
    thread_local Scratch scratch;
    for (std::size_t g = job * per_job; g < std::min(groups.size(), (job + 1) * per_job); ++g)
      tree.group_accelerations(groups[g], G, eps2, theta, scratch, a);
  };
  if (pool) pool->run(jobs, run);
  else
    for (std::size_t job = 0; job < jobs; ++job) run(job);
  for (std::uint32_t k = 0; k < x.size(); ++k) {
    const std::uint32_t i = tree.particle_at(k);
    force[i] = force[i] + m[i] * a[k];
  }
}

void tree_gravity(const std::vector<Vector3>& x, const std::vector<double>& m, double G, double softening, double theta,
                  std::size_t threads, std::vector<Vector3>& force) {
  if (threads <= 1) return tree_gravity(x, m, G, softening, theta, nullptr, force);
  WorkerPool pool(threads);
  tree_gravity(x, m, G, softening, theta, &pool, force);
}

}  // namespace aggkit

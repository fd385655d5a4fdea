#include "particle/dem/direct_gravity.hpp"

#include <algorithm>
#include <cmath>

#include "particle/common/simd_clones.hpp"

namespace aggkit {

namespace {

struct Tile {
  std::size_t a, b, offset_a, offset_b;  // blocks a <= b; buffer offsets of their particles
};

// Block `a` against block `b` (b > a), or the pairs i < j within block a (b == a). Coordinates and masses
// as arrays; partial forces into fa (block a) and fb (block b, the same buffer when b == a).
AGGKIT_SIMD_CLONES void run_tile(const double* px, const double* py, const double* pz, const double* pm, std::size_t a0, std::size_t a1,
              std::size_t b0, std::size_t b1, bool same, double G, double eps2, double* fax, double* fay, double* faz,
              double* fbx, double* fby, double* fbz) {
  for (std::size_t i = a0; i < a1; ++i) {
    const double xi = px[i], yi = py[i], zi = pz[i], gi = G * pm[i];
    double fx = 0, fy = 0, fz = 0;
    const std::size_t j0 = same ? i + 1 : b0;
    double* bx = fbx - b0;
    double* by = fby - b0;
    double* bz = fbz - b0;
#pragma omp simd reduction(+ : fx, fy, fz)
    for (std::size_t j = j0; j < b1; ++j) {
      const double dx = px[j] - xi, dy = py[j] - yi, dz = pz[j] - zi;  // open or walls: no images
      const double r2 = dx * dx + dy * dy + dz * dz;
      // |F| = G m_i m_j / (r² + ε²) along the pair [Trivino2025, eq. 1]; nothing between coincident particles.
      // Branch-free (a condition around the division keeps the loop from vectorising).
      const double apart = double(r2 > 0);
      const double s = apart * gi * pm[j] / (std::sqrt(r2) * (r2 + eps2) + (1 - apart));
      fx += s * dx, fy += s * dy, fz += s * dz;
      bx[j] -= s * dx, by[j] -= s * dy, bz[j] -= s * dz;
    }
    fax[i - a0] += fx, fay[i - a0] += fy, faz[i - a0] += fz;
  }
}

}  // namespace

void direct_gravity(const std::vector<Vector3>& x, const std::vector<double>& m, double G, double softening, std::size_t threads,
                    std::vector<Vector3>& force) {
  if (threads <= 1) return direct_gravity(x, m, G, softening, nullptr, force);
  WorkerPool pool(threads);
  direct_gravity(x, m, G, softening, &pool, force);
}

void direct_gravity(const std::vector<Vector3>& x, const std::vector<double>& m, double G, double softening, WorkerPool* pool,
                    std::vector<Vector3>& force) {
  const std::size_t n = x.size();
  if (n < 2) return;
  std::vector<double> px(n), py(n), pz(n);
  for (std::size_t i = 0; i < n; ++i) px[i] = x[i][0], py[i] = x[i][1], pz[i] = x[i][2];
  // K depends on N only: blocks of at least 64 particles, at most 16 of them.
  const std::size_t k_blocks = std::clamp<std::size_t>(n / 64, 1, 16);
  auto block_begin = [&](std::size_t c) { return c * n / k_blocks; };
  std::vector<Tile> tiles;
  std::size_t storage = 0;
  for (std::size_t a = 0; a < k_blocks; ++a)
    for (std::size_t b = a; b < k_blocks; ++b) {
      Tile t{a, b, storage, 0};
      storage += block_begin(a + 1) - block_begin(a);
      t.offset_b = storage;
      if (b != a) storage += block_begin(b + 1) - block_begin(b);
      tiles.push_back(t);
    }
  std::vector<double> fx(storage, 0.0), fy(storage, 0.0), fz(storage, 0.0);
  const double eps2 = softening * softening;
  auto run = [&](const Tile& t) {
    const std::size_t oa = t.offset_a, ob = t.a == t.b ? t.offset_a : t.offset_b;
    run_tile(px.data(), py.data(), pz.data(), m.data(), block_begin(t.a), block_begin(t.a + 1), block_begin(t.b), block_begin(t.b + 1),
             t.a == t.b, G, eps2, fx.data() + oa, fy.data() + oa, fz.data() + oa, fx.data() + ob, fy.data() + ob, fz.data() + ob);
  };
  if (pool) pool->run(tiles.size(), [&](std::size_t t) { run(tiles[t]); });
  else
    for (const Tile& t : tiles) run(t);
  // Reduction in tile order (a, b ascending), one particle at a time.
  for (const Tile& t : tiles) {
    for (std::size_t i = block_begin(t.a), k = t.offset_a; i < block_begin(t.a + 1); ++i, ++k)
      force[i] = force[i] + Vector3{fx[k], fy[k], fz[k]};
    if (t.b != t.a)
      for (std::size_t j = block_begin(t.b), k = t.offset_b; j < block_begin(t.b + 1); ++j, ++k)
        force[j] = force[j] + Vector3{fx[k], fy[k], fz[k]};
  }
}

}  // namespace aggkit

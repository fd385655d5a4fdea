#include "solvers/low_rank.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace aggkit {

double separable_entry(const SeparableForm& form, std::size_t i, std::size_t j) {
  double sum = 0.0;
  for (std::size_t p = 0; p < form.rank(); ++p)
    for (std::size_t q = 0; q < form.rank(); ++q)
      if (form.coupling[p][q] != 0.0)
        sum += form.coupling[p][q] * form.features[p][i - 1] * form.features[q][j - 1];
  return sum;
}

namespace {

// Rows on which the error is measured (1-based sizes); all rows for small N. Every row costs N kernel
// evaluations: at N = 2000 all rows took about as long as 400 right-hand sides of the ballistic kernel
// (a third of a run to t = 100 at rtol 1e-10), the 65 sampled rows a thirtieth of that.
std::vector<std::size_t> check_rows(std::size_t N) {
  std::vector<std::size_t> rows;
  if (N <= 256) {
    for (std::size_t i = 1; i <= N; ++i) rows.push_back(i);
    return rows;
  }
  for (std::size_t i = 1; i <= 16; ++i) rows.push_back(i);
  for (int r = 0; r < 24; ++r)  // log-spaced over 17 .. N - 1
    rows.push_back(std::size_t(17.0 * std::pow(double(N - 1) / 17.0, (r + 0.5) / 24.0)));
  std::uint64_t state = 0x9E3779B97F4A7C15ull;  // splitmix64: fixed, reproducible sample
  for (int r = 0; r < 24; ++r) {
    state += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = state;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    rows.push_back(17 + z % (N - 17));
  }
  rows.push_back(N);
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  return rows;
}

struct Coupling {
  std::size_t p, q;
  double c;
};

std::vector<Coupling> nonzero_couplings(const SeparableForm& form) {
  std::vector<Coupling> couplings;
  for (std::size_t p = 0; p < form.rank(); ++p)
    for (std::size_t q = 0; q < form.rank(); ++q)
      if (form.coupling[p][q] != 0.0) couplings.push_back({p, q, form.coupling[p][q]});
  return couplings;
}

}  // namespace

double separable_form_error(const SeparableForm& form,
                            const std::function<double(std::size_t, std::size_t)>& kernel,
                            std::size_t N, std::size_t* checked_entries) {
  const std::size_t R = form.rank();
  const auto couplings = nonzero_couplings(form);
  const auto rows = check_rows(N);
  // K̃_ij = Σ_q left_q(i) φ_q(j), left_q(i) = Σ_p C_pq φ_p(i): one row of `left` per checked size.
  std::vector<std::vector<double>> left(rows.size(), std::vector<double>(R, 0.0));
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (const auto& [p, q, c] : couplings) left[r][q] += c * form.features[p][rows[r] - 1];
  double worst = 0.0;
  std::size_t count = 0;
  // Columns in chunks, so that the features' chunk stays in cache while every checked row uses it.
  constexpr std::size_t chunk = 1024;
  std::vector<double> approx(chunk);
  for (std::size_t j0 = 0; j0 < N; j0 += chunk) {
    const std::size_t width = std::min(chunk, N - j0);
    for (std::size_t r = 0; r < rows.size(); ++r) {
      std::fill(approx.begin(), approx.begin() + std::ptrdiff_t(width), 0.0);
      for (std::size_t q = 0; q < R; ++q) {
        const double w = left[r][q];
        if (w == 0.0) continue;
        const double* phi = form.features[q].data() + j0;
        for (std::size_t j = 0; j < width; ++j) approx[j] += w * phi[j];
      }
      for (std::size_t j = 0; j < width; ++j) {
        const double exact = kernel(rows[r], j0 + j + 1);
        worst = std::max(worst, std::abs(approx[j] - exact) / std::abs(exact));
      }
      count += width;
    }
  }
  if (N > 2048)  // the diagonal too (by symmetry the checked rows also cover those columns)
    for (std::size_t i = 1; i <= N; i += 7) {
      double approx_ii = 0.0;
      for (const auto& [p, q, c] : couplings) approx_ii += c * form.features[p][i - 1] * form.features[q][i - 1];
      const double exact = kernel(i, i);
      worst = std::max(worst, std::abs(approx_ii - exact) / std::abs(exact));
      ++count;
    }
  if (checked_entries) *checked_entries = count;
  return worst;
}

namespace {

using Real = long double;  // the elimination's arithmetic (see the header)

// Every size up to `all_up_to`, then a geometric grid of ratio `ratio`, then N.
std::vector<std::size_t> skeleton_sizes(std::size_t N, std::size_t all_up_to, double ratio) {
  std::vector<std::size_t> sizes;
  for (std::size_t i = 1; i <= std::min(N, all_up_to); ++i) sizes.push_back(i);
  double x = double(all_up_to);
  while (sizes.back() < N) {
    x *= ratio;
    const std::size_t k = std::min(N, std::size_t(std::llround(x)));
    if (k > sizes.back()) sizes.push_back(k);
  }
  return sizes;
}

// Symmetric elimination of the skeleton matrix: the pivots (skeleton indices, in order), their blocks
// (1 or 2 pivots), each block's inverse pivot block, and the substitution coefficients
// G[s][t] = Σ_{s' in block(s)} Binv[s][s'] E_{block(s)}(σ_s', σ_t) for pivots t of later blocks, where
// E_b is the residual before block b. A size i's residual values at the pivots then follow from its
// kernel values k_t = K(i, σ_t) by u_t = k_t − Σ_{s in earlier blocks} u_s G[s][t].
struct Elimination {
  std::vector<std::size_t> pivots;                    // skeleton indices
  std::vector<std::size_t> block_start;               // first pivot of each block; back() = pivots.size()
  std::vector<std::vector<Real>> inverse;             // per block, row-major 1×1 or 2×2
  std::vector<std::vector<Real>> G;                   // G[s][t], pivots × pivots
};

Elimination eliminate(std::vector<Real> E, std::size_t m, double threshold, std::size_t max_rank) {
  // Bunch–Parlett [BunchParlett1971]: a 1×1 pivot on the largest diagonal entry when it is at least
  // α times the largest entry, else a 2×2 pivot on the largest entry and its mirror; α = (1 + √17) / 8
  // bounds the element growth.
  const Real alpha = (1.0L + std::sqrt(17.0L)) / 8.0L;
  Elimination result;
  std::vector<std::vector<Real>> pivot_rows;  // E_b(σ_p, :) at the time of each pivot's block
  result.block_start.push_back(0);
  Real best = std::numeric_limits<Real>::infinity();
  int stalled = 0;
  while (result.pivots.size() < max_rank) {
    Real emax = 0.0L, dmax = 0.0L;
    std::size_t a = 0, b = 0, c = 0;
    for (std::size_t i = 0; i < m; ++i) {
      const Real d = std::abs(E[i * m + i]);
      if (d > dmax) dmax = d, c = i;
      for (std::size_t j = i; j < m; ++j)
        if (std::abs(E[i * m + j]) > emax) emax = std::abs(E[i * m + j]), a = i, b = j;
    }
    if (emax <= threshold) break;
    // A tolerance below the round-off floor cannot be met: stop when the residual has not halved for 8
    // steps; the measured error then reports what was reached.
    stalled = emax < 0.5L * best ? 0 : stalled + 1;
    best = std::min(best, emax);
    if (stalled >= 8) break;
    std::vector<std::size_t> block;
    if (dmax >= alpha * emax || a == b) block = {dmax >= alpha * emax ? c : a};
    else block = {a, b};
    if (result.pivots.size() + block.size() > max_rank) break;
    std::vector<Real> inv;
    if (block.size() == 1) {
      inv = {1.0L / E[block[0] * m + block[0]]};
    } else {
      const Real p = E[a * m + a], q = E[a * m + b], r = E[b * m + b], det = p * r - q * q;
      inv = {r / det, -q / det, -q / det, p / det};
    }
    for (std::size_t s : block) pivot_rows.emplace_back(E.begin() + std::ptrdiff_t(s * m), E.begin() + std::ptrdiff_t((s + 1) * m));
    const std::size_t first = result.pivots.size(), k = block.size();
    // E -= E(:, block) Binv E(block, :), symmetric: the block's rows stand for its columns.
    for (std::size_t i = 0; i < m; ++i) {
      Real w[2] = {0.0L, 0.0L};
      for (std::size_t s = 0; s < k; ++s)
        for (std::size_t t = 0; t < k; ++t) w[t] += pivot_rows[first + s][i] * inv[s * k + t];
      for (std::size_t t = 0; t < k; ++t) {
        const Real* row = pivot_rows[first + t].data();
        Real* e = E.data() + i * m;
        for (std::size_t j = 0; j < m; ++j) e[j] -= w[t] * row[j];
      }
    }
    for (std::size_t s : block) {  // eliminated exactly: no round-off residue to pick again
      for (std::size_t j = 0; j < m; ++j) E[s * m + j] = E[j * m + s] = 0.0L;
      result.pivots.push_back(s);
    }
    result.inverse.push_back(std::move(inv));
    result.block_start.push_back(result.pivots.size());
  }
  const std::size_t R = result.pivots.size();
  result.G.assign(R, std::vector<Real>(R, 0.0L));
  for (std::size_t blk = 0; blk + 1 < result.block_start.size(); ++blk) {
    const std::size_t first = result.block_start[blk], k = result.block_start[blk + 1] - first;
    for (std::size_t s = 0; s < k; ++s)
      for (std::size_t t = result.block_start[blk + 1]; t < R; ++t) {
        Real g = 0.0L;
        for (std::size_t s2 = 0; s2 < k; ++s2)
          g += result.inverse[blk][s * k + s2] * pivot_rows[first + s2][result.pivots[t]];
        result.G[first + s][t] = g;
      }
  }
  return result;
}

SeparableForm factorise(const std::function<double(std::size_t, std::size_t)>& kernel, std::size_t N,
                        double tolerance, std::size_t all_up_to, double ratio) {
  const auto sizes = skeleton_sizes(N, all_up_to, ratio);
  const std::size_t m = sizes.size();
  std::vector<Real> E(m * m);
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = i; j < m; ++j) {
      const double k = kernel(sizes[i], sizes[j]);
      E[i * m + j] = E[j * m + i] = k;
      smallest = std::min(smallest, std::abs(k));
    }
  // The skeleton residual below a twentieth of the tolerance on the smallest entry: the entries between
  // skeleton points, interpolated by the factors, keep the rest of the margin (measured below).
  const Elimination elim = eliminate(std::move(E), m, 0.05 * tolerance * smallest, std::min<std::size_t>(m, 400));
  const std::size_t R = elim.pivots.size();
  std::vector<std::size_t> pivot_size(R);
  for (std::size_t t = 0; t < R; ++t) pivot_size[t] = sizes[elim.pivots[t]];

  // Each block's inverse, diagonalised: Binv = Q diag(c) Q^T (a 2×2 symmetric block by a Jacobi rotation).
  SeparableForm form;
  form.exact = false;
  form.tolerance = tolerance;
  std::vector<Real> mix(R * 2, 0.0L);  // feature r = Σ_{s in its block} mix[r][s - first] u_s
  std::vector<double> coupling(R);
  for (std::size_t blk = 0; blk + 1 < elim.block_start.size(); ++blk) {
    const std::size_t first = elim.block_start[blk];
    const auto& B = elim.inverse[blk];
    if (elim.block_start[blk + 1] - first == 1) {
      mix[first * 2] = 1.0L;
      coupling[first] = double(B[0]);
      continue;
    }
    const Real p = B[0], q = 0.5L * (B[1] + B[2]), r = B[3];
    const Real theta = 0.5L * std::atan2(2.0L * q, p - r), cs = std::cos(theta), sn = std::sin(theta);
    // Q = [[cs, -sn], [sn, cs]]: eigenvalues p cs² + 2 q cs sn + r sn² and p sn² − 2 q cs sn + r cs².
    coupling[first] = double(p * cs * cs + 2.0L * q * cs * sn + r * sn * sn);
    coupling[first + 1] = double(p * sn * sn - 2.0L * q * cs * sn + r * cs * cs);
    mix[first * 2] = cs, mix[first * 2 + 1] = sn;
    mix[(first + 1) * 2] = -sn, mix[(first + 1) * 2 + 1] = cs;
  }
  std::vector<std::size_t> block_of(R);
  for (std::size_t blk = 0; blk + 1 < elim.block_start.size(); ++blk)
    for (std::size_t t = elim.block_start[blk]; t < elim.block_start[blk + 1]; ++t) block_of[t] = blk;

  // Every size's residual values at the pivots (R kernel values, forward substitution), then the features.
  form.features.assign(R, std::vector<double>(N));
  std::vector<Real> u(R);
  for (std::size_t i = 1; i <= N; ++i) {
    for (std::size_t t = 0; t < R; ++t) {
      Real v = kernel(i, pivot_size[t]);
      const std::size_t before = elim.block_start[block_of[t]];
      for (std::size_t s = 0; s < before; ++s) v -= u[s] * elim.G[s][t];
      u[t] = v;
    }
    for (std::size_t t = 0; t < R; ++t) {
      const std::size_t first = elim.block_start[block_of[t]];
      Real w = 0.0L;
      for (std::size_t s = first; s < elim.block_start[block_of[t] + 1]; ++s) w += mix[t * 2 + (s - first)] * u[s];
      form.features[t][i - 1] = double(w);
    }
  }
  form.coupling.assign(R, std::vector<double>(R, 0.0));
  for (std::size_t r = 0; r < R; ++r) form.coupling[r][r] = coupling[r];
  form.max_relative_error = separable_form_error(form, kernel, N, &form.checked_entries);
  return form;
}

}  // namespace

SeparableForm cross_approximation(const std::function<double(std::size_t, std::size_t)>& kernel,
                                  std::size_t N, double tolerance) {
  if (!(tolerance > 0.0)) throw std::invalid_argument("cross_approximation: tolerance must be > 0");
  if (N == 0) throw std::invalid_argument("cross_approximation: N must be > 0");
  SeparableForm form = factorise(kernel, N, tolerance, 64, 1.03);
  if (form.max_relative_error > tolerance && N > 64) {  // a denser skeleton, once
    SeparableForm refined = factorise(kernel, N, tolerance, 256, 1.005);
    if (refined.max_relative_error < form.max_relative_error) form = std::move(refined);
  }
  return form;
}

}  // namespace aggkit

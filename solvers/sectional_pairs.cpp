#include "solvers/sectional_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "analysis/input_error.hpp"
#include "solvers/size_grid.hpp"

namespace aggkit {

namespace {

// The shortest diagonal stretch of one offset stored as a diagonal run: shorter ones (the unit-spaced sizes,
// where the offset changes with every pair of a diagonal) stay in their rows.
constexpr std::size_t min_diagonal_run = 8;

}  // namespace

// accumulate's loops in AVX2 where the processor has it, SSE2 elsewhere: the same operations element by element
// (no FMA contraction, the sums in the same order), so the same results bit for bit.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define AGGKIT_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define AGGKIT_VECTOR_CLONES
#endif

// Every pair (i ≤ j) row by row: its weight, its stencil (first pivot << 3 | size, 1 to 4; first pivot M: the
// aggregate leaves the grid) and the shares given to pivots first .. first + 3 (0 beyond the stencil). The
// stencil's last share is 1 − the others (Σ w_m = 1 is one of the conditions that define them, and number
// stays exact to round-off).
struct SectionalPairs::Table {
  std::size_t M;
  std::vector<double> weight;
  std::vector<std::uint32_t> stencil;
  std::vector<double> share[max_stencil];
  std::vector<std::size_t> row;  // index of (i, i)

  Table(const AggregationModel& model, const std::vector<double>& x) : M(x.size()), row(x.size()) {
    const std::size_t P = M * (M + 1) / 2;
    weight.reserve(P);
    stencil.reserve(P);
    for (auto& s : share) s.reserve(P);
    for (std::size_t i = 0; i < M; ++i) {
      row[i] = weight.size();
      for (std::size_t j = i; j < M; ++j) add_pair(model, x, i, j);
    }
  }
  std::size_t at(std::size_t i, std::size_t j) const { return row[i] + (j - i); }
  std::size_t target(std::size_t at) const { return stencil[at] >> 3; }
  std::uint32_t width(std::size_t at) const { return stencil[at] & 7; }

  void add_pair(const AggregationModel& model, const std::vector<double>& x, std::size_t i, std::size_t j) {
    const double v = x[i] + x[j];
    double w = (i == j ? 0.5 : 1.0) * model.kernel.at(x[i], x[j]);
    double shares[max_stencil] = {0.0, 0.0, 0.0, 0.0};
    std::uint32_t s = std::uint32_t(M) << 3;  // leaves the grid (drop) or does not collide (cutoff)
    if (v > x.back()) {
      if (model.truncation == Truncation::cutoff) w = 0.0;
    } else {
      const PivotShare ps = pivot_share(x, v, model.grid.scheme, model.grid.resolved);
      s = std::uint32_t(ps.first) << 3 | std::uint32_t(ps.count);
      double rest = 1.0;
      for (int m = 0; m + 1 < ps.count; ++m) rest -= shares[m] = ps.weight[m];
      shares[ps.count - 1] = rest;
    }
    weight.push_back(w);
    stencil.push_back(s);
    for (std::size_t m = 0; m < max_stencil; ++m) share[m].push_back(shares[m]);
  }
};

SectionalPairs::SectionalPairs(const AggregationModel& model, const std::vector<double>& x) : x_(x) {
  const std::size_t M = x_.size();
  if (M > max_classes)
    throw InputError("grid", model.grid.describe() + " on N = " + std::to_string(model.size) + " (" +
                                 std::to_string(M) + " classes)",
                     "at most " + std::to_string(max_classes) + " size classes (raise grid.ratio or lower grid.resolved)");
  const Table table(model, x_);
  std::vector<std::size_t> near_end(M, M);  // row i's pairs are far from column near_end[i] to near_top − 1
  std::size_t near_top = M;
  if (const Kernel::Factors* factors = model.kernel.exact_factors(); factors && M >= 3)
    build_far_field(table, *factors, near_end, near_top);
  build_runs(table, near_end, near_top);
}

SectionalPairs::~SectionalPairs() = default;

std::size_t SectionalPairs::far_pairs() const { return far_ ? far_->pairs() : 0; }

// The far field (solvers/sectional_far_field.hpp): column j's partners i < I_j whose pairs stay within
// (x_j, x_{j+1}) on one stencil with the stored shares equal, to 1e-12, to its Lagrange polynomials. I_j is
// made nondecreasing (the smallest I over the columns above it), up to a top column near_top chosen to keep
// the most far pairs; the columns from near_top on (the grid's end, where the last intervals may be short)
// stay near. Row i's far pairs are then the columns from near_end[i] to near_top − 1.
void SectionalPairs::build_far_field(const Table& table, const Kernel::Factors& factors,
                                     std::vector<std::size_t>& near_end, std::size_t& near_top) {
  const std::size_t M = x_.size();
  far_ = std::make_unique<SectionalFarField>(x_, factors);
  std::vector<std::uint32_t> raw(M, 0);
  for (std::size_t j = 1; j + 1 < M; ++j) raw[j] = std::uint32_t(far_partners(table, j));
  // The top column: the one whose nondecreasing counts below it sum to the most pairs (the last 32 tried).
  std::size_t best_top = M, best_pairs = 0;
  for (std::size_t k = 0; k < 32 && k + 2 <= M; ++k) {
    const std::size_t top = M - 1 - k;
    std::size_t pairs = 0, running = std::size_t(-1);
    for (std::size_t j = top; j-- > 0;) pairs += running = std::min<std::size_t>(running, raw[j]);
    if (pairs > best_pairs) best_pairs = pairs, best_top = top;
  }
  if (best_pairs == 0) {
    far_.reset();
    return;
  }
  std::vector<std::uint32_t> count(M, 0);
  std::uint32_t running = std::uint32_t(-1);
  for (std::size_t j = best_top; j-- > 0;) count[j] = running = std::min(running, raw[j]);
  near_top = best_top;
  for (std::size_t i = 0, j = 0; i < M; ++i) {
    while (j < near_top && count[j] <= i) ++j;
    near_end[i] = j;  // the first column with i among its far partners (near_top: none)
  }
  far_->set_counts(std::move(count));
}

// How many partners i = 0, 1, ... of column j (i < j) the far field can take: their aggregates stay below
// x_{j+1}, on pair (0, j)'s stencil, with the shares its polynomials give.
std::size_t SectionalPairs::far_partners(const Table& table, std::size_t j) {
  const std::size_t M = x_.size();
  const std::uint32_t stencil = table.stencil[table.at(0, j)];
  const std::size_t first = stencil >> 3, width = stencil & 7;
  if (first >= M || width == 0 || !(x_[0] + x_[j] < x_[j + 1])) return 0;
  far_->set_stencil(j, first, width);
  std::size_t i = 0;
  for (; i < j; ++i) {
    const std::size_t at = table.at(i, j);
    if (!(x_[i] + x_[j] < x_[j + 1]) || table.stencil[at] != stencil || table.weight[at] == 0.0) break;
    bool same = true;
    for (std::size_t m = 0; m < width; ++m)
      same = same && std::abs(table.share[m][at] - far_->share(j, m, x_[i])) <= 1e-12;
    if (!same) break;
  }
  return i;
}

// The runs: first the near band's diagonal stretches of one offset at least min_diagonal_run long, then what
// is left of each row, cut where the offset or the kind of pair (near, leaving the grid, far) changes. Pairs
// of weight 0 (cutoff's pairs beyond N) are left out.
void SectionalPairs::build_runs(const Table& table, const std::vector<std::size_t>& near_end, std::size_t near_top) {
  const std::size_t M = x_.size();
  auto far = [&](std::size_t i, std::size_t j) { return near_end[i] <= j && j < near_top; };
  auto offset = [&](std::size_t at, std::size_t j) { return std::int32_t(table.target(at)) - std::int32_t(j); };
  std::vector<char> taken(table.weight.size(), 0);
  std::vector<Run> diagonal, rows, leaking, far_rows;
  for (std::size_t l = 0; l < M; ++l) {
    std::size_t begin = 0;
    bool open = false;  // pairs (begin, begin + l) .. (i − 1, i − 1 + l): summed, one offset
    for (std::size_t i = 0; i + l <= M; ++i) {
      const std::size_t j = i + l, at = j < M ? table.at(i, j) : 0;
      const bool summed = j < M && table.weight[at] != 0.0 && table.target(at) < M && !far(i, j);
      if (summed && open && offset(at, j) == offset(table.at(begin, begin + l), begin + l)) continue;
      if (open && i - begin >= min_diagonal_run) {
        diagonal.push_back(Run{std::uint32_t(begin), std::uint32_t(begin + l), std::uint32_t(i - begin),
                               offset(table.at(begin, begin + l), begin + l), 0, true, 0});
        for (std::size_t k = begin; k < i; ++k) taken[table.at(k, k + l)] = 1;
      }
      open = summed;
      begin = i;
    }
  }
  for (std::size_t i = 0; i < M; ++i) {
    Run* open = nullptr;
    int open_kind = -1;
    for (std::size_t j = i; j < M; ++j) {
      const std::size_t at = table.at(i, j);
      if (taken[at] || table.weight[at] == 0.0) {
        open = nullptr;
        continue;
      }
      const int kind = table.target(at) >= M ? 1 : far(i, j) ? 2 : 0;
      const std::int32_t o = kind == 1 ? 0 : offset(at, j);
      if (open && open_kind == kind && open->offset == o) {
        ++open->length;
        continue;
      }
      auto& list = kind == 0 ? rows : kind == 1 ? leaking : far_rows;
      list.push_back(Run{std::uint32_t(i), std::uint32_t(j), 1, o, 0, false, 0});
      open = &list.back();
      open_kind = kind;
    }
  }
  for (auto* list : {&diagonal, &rows}) runs_.insert(runs_.end(), list->begin(), list->end());
  leak_begin_ = runs_.size();
  runs_.insert(runs_.end(), leaking.begin(), leaking.end());
  summed_runs_ = runs_.size();
  runs_.insert(runs_.end(), far_rows.begin(), far_rows.end());
  for (Run& run : runs_) add_run(table, run);
}

// Stores a run's weights and shares (its count: the widest stencil among its pairs; 0 for those leaving).
void SectionalPairs::add_run(const Table& table, Run& run) {
  const std::size_t M = x_.size();
  std::uint32_t count = 0;
  for (std::uint32_t k = 0; k < run.length; ++k) {
    const std::size_t at = table.at(run.i0 + (run.diagonal ? k : 0), run.j0 + k);
    if (table.target(at) < M) count = std::max(count, table.width(at));
  }
  run.count = count;
  run.at = data_.size();
  data_.resize(run.at + (count + 1) * std::size_t(run.length), 0.0);
  for (std::uint32_t k = 0; k < run.length; ++k) {
    const std::size_t at = table.at(run.i0 + (run.diagonal ? k : 0), run.j0 + k);
    data_[run.at + k] = table.weight[at];
    for (std::uint32_t m = 0; m < count; ++m) data_[run.at + (m + 1) * run.length + k] = table.share[m][at];
  }
  longest_run_ = std::max<std::size_t>(longest_run_, run.length);
}

// Row by row of the runs, in passes that each stream one array: the run's pair rates r_k = s w_k (u_i v_j +
// u_j v_i), their collision losses summed per class (subtracted as L + λL once per class at the end, never
// (1 + λ)L: at λ of a few ulp of 1, 1 + λ rounds λ by up to 1 %), and share by share the aggregates' gains,
// which go to consecutive entries along a run. The shattered mass λ Σ (x_i + x_j) r_ij is λ Σ_k x_k L_k.
AGGKIT_VECTOR_CLONES void SectionalPairs::accumulate(double lambda, std::span<const double> u, std::span<const double> v,
                                std::span<double> out, double scale, Scratch& scratch) const {
  const std::size_t M = x_.size();
  scratch.rate.resize(longest_run_);
  scratch.lost.assign(M, 0.0);
  scratch.gain.assign(M + max_stencil, 0.0);
  double* __restrict rate = scratch.rate.data();
  double* lost = scratch.lost.data();
  double* gain = scratch.gain.data();
  for (std::size_t r = 0; r < summed_runs_; ++r) {
    const Run& run = runs_[r];
    const std::size_t n = run.length;
    const double* __restrict w = data_.data() + run.at;
    const double* __restrict uj = u.data() + run.j0;
    const double* __restrict vj = v.data() + run.j0;
    if (run.diagonal) {
      const double* __restrict ui = u.data() + run.i0;
      const double* __restrict vi = v.data() + run.i0;
      for (std::size_t k = 0; k < n; ++k) rate[k] = scale * w[k] * (ui[k] * vj[k] + uj[k] * vi[k]);
      double* __restrict to = lost + run.i0;
      for (std::size_t k = 0; k < n; ++k) to[k] += rate[k];
    } else {
      const double ui = u[run.i0], vi = v[run.i0];
      for (std::size_t k = 0; k < n; ++k) rate[k] = scale * w[k] * (ui * vj[k] + uj[k] * vi);
      double sum = 0.0;
      for (std::size_t k = 0; k < n; ++k) sum += rate[k];
      lost[run.i0] += sum;
    }
    double* __restrict to = lost + run.j0;
    for (std::size_t k = 0; k < n; ++k) to[k] += rate[k];
    for (std::uint32_t m = 0; m < run.count; ++m) {
      const double* __restrict share = w + (m + 1) * n;
      double* __restrict into = gain + (std::ptrdiff_t(run.j0) + run.offset + m);
      for (std::size_t k = 0; k < n; ++k) into[k] += share[k] * rate[k];
    }
  }
  double monomers = 0.0;
  for (std::size_t k = 0; k < M; ++k) {
    gain[k] -= lost[k] + lambda * lost[k];
    monomers += x_[k] * lost[k];
  }
  if (far_) far_->accumulate(lambda, u, v, scale, gain, monomers, scratch.far);
  gain[0] += lambda * monomers;
  for (std::size_t k = 0; k < M; ++k) out[k] += gain[k];
}

double SectionalPairs::leak_rate(std::span<const double> n) const {
  double leak = 0.0;
  for (std::size_t r = leak_begin_; r < summed_runs_; ++r) {
    const Run& run = runs_[r];
    for (std::uint32_t k = 0; k < run.length; ++k) {
      const std::size_t i = run.i0 + (run.diagonal ? k : 0), j = run.j0 + k;
      leak += (x_[i] + x_[j]) * data_[run.at + k] * n[i] * n[j];
    }
  }
  return leak;
}

void SectionalPairs::leak_gradient(std::span<const double> n, std::span<double> gradient) const {
  std::fill(gradient.begin(), gradient.end(), 0.0);
  for (std::size_t r = leak_begin_; r < summed_runs_; ++r) {
    const Run& run = runs_[r];
    for (std::uint32_t k = 0; k < run.length; ++k) {
      const std::size_t i = run.i0 + (run.diagonal ? k : 0), j = run.j0 + k;
      const double c = (x_[i] + x_[j]) * data_[run.at + k];
      gradient[i] += c * n[j];
      gradient[j] += c * n[i];
    }
  }
}

// Calls add(row, column, ∂f_row/∂N_column contribution) for every nonzero contribution of pair k of `run`.
template <class Add>
void SectionalPairs::pair_entries(const Run& run, std::uint32_t k, double lambda, std::span<const double> n, Add&& add) const {
  const double* w = data_.data() + run.at;
  const std::size_t i = run.i0 + (run.diagonal ? k : 0), j = run.j0 + k;
  // ∂(w N_i N_j)/∂N_i = w N_j and ∂/∂N_j = w N_i (both 2 w N_i on the diagonal).
  for (int side = 0; side < 2; ++side) {
    const std::size_t column = side == 0 ? i : j;
    const double d = w[k] * (side == 0 ? n[j] : n[i]);
    if (d == 0.0) continue;
    add(i, column, -(d + lambda * d));
    add(j, column, -(d + lambda * d));
    add(0, column, lambda * (x_[i] + x_[j]) * d);
    for (std::uint32_t m = 0; m < run.count; ++m)
      if (const double share = w[(m + 1) * run.length + k]; share != 0.0)
        add(std::size_t(std::ptrdiff_t(j) + run.offset + m), column, share * d);
  }
}

void SectionalPairs::dense(double lambda, std::span<const double> n, std::span<double> jacobian) const {
  const std::size_t M = x_.size();
  std::fill(jacobian.begin(), jacobian.end(), 0.0);
  const auto add = [&](std::size_t row, std::size_t column, double value) { jacobian[row * M + column] += value; };
  for (const Run& run : runs_)
    for (std::uint32_t k = 0; k < run.length; ++k) pair_entries(run, k, lambda, n, add);
}

// Where a pair (i, j) has i ≥ 1, j ≥ i + 2 and its stencil starts at or beyond i + 2 (all but O(M) pairs), its
// only entries on the diagonal, the subdiagonal or the monomer column are its losses ∂/∂N_i at (i, i) and
// ∂/∂N_j at (j, j), and the gains ∂/∂N_j of its shares for pivots j and j + 1: those are summed directly, one
// run at a time, and the other pairs give every entry (pair_entries).
void SectionalPairs::monomer_coupling(double lambda, std::span<const double> n, std::span<double> diagonal,
                                      std::span<double> subdiagonal, std::span<double> monomer_column) const {
  for (auto part : {diagonal, subdiagonal, monomer_column}) std::fill(part.begin(), part.end(), 0.0);
  const auto entry = [&](std::size_t row, std::size_t column, double value) {
    if (column == 0 && row >= 1) monomer_column[row] += value;
    else if (row == column) diagonal[row] += value;
    else if (row == column + 1) subdiagonal[row] += value;
  };
  for (const Run& run : runs_) {
    const double* w = data_.data() + run.at;
    for (std::uint32_t k = 0; k < run.length; ++k) {
      const std::size_t i = run.i0 + (run.diagonal ? k : 0), j = run.j0 + k;
      if (i == 0 || j <= i + 1 || std::ptrdiff_t(j) + run.offset <= std::ptrdiff_t(i) + 1) {
        pair_entries(run, k, lambda, n, entry);
        continue;
      }
      const double d_i = w[k] * n[j], d_j = w[k] * n[i];  // ∂(w N_i N_j)/∂N_i and /∂N_j
      diagonal[i] -= d_i + lambda * d_i;
      diagonal[j] -= d_j + lambda * d_j;
      for (std::uint32_t m = 0; m < run.count; ++m) {
        const std::ptrdiff_t past = run.offset + std::ptrdiff_t(m);  // the pivot j + past
        if (past != 0 && past != 1) continue;
        if (const double share = w[(m + 1) * run.length + k]; share != 0.0)
          (past == 0 ? diagonal[j] : subdiagonal[j + 1]) += share * d_j;
      }
    }
  }
}

}  // namespace aggkit

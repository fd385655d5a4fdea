// The aggregation-shattering right-hand side on a graded size grid (solvers/size_grid.hpp): aggregates
// between pivots shared by the four-moment shares (the default) or the three-moment shares [Alopaeus2006],
// or by the fixed-pivot technique [Kumar1996].
//
// Derivation. The unknowns N_i are the numbers of clusters at the pivots x_1 < ... < x_M = N. A collision
// of classes i and j happens at rate K(x_i, x_j) N_i N_j per unordered pair (½ K N_i² for i = j). With
// probability 1/(1+λ) it aggregates: the new cluster of size v = x_i + x_j is shared among the pivots
// around it with weights w_m (pivot_share, solvers/size_grid.hpp). Fixed pivot: x_p ≤ v < x_{p+1} gets
// η = (x_{p+1} - v)/(x_{p+1} - x_p) to p and 1 - η to p + 1, the only two shares that keep both number
// (η + (1 - η) = 1) and mass (η x_p + (1 - η) x_{p+1} = v) [Kumar1996]. Three moments: the nearest three
// pivots q, q+1, q+2 get the Lagrange weights w_m = Π_{l≠m} (v - x_l)/(x_m - x_l), the only three shares
// with Σ w_m x_m^k = v^k for k = 0, 1, 2, which also keep the second moment and so add no numerical
// spread to the aggregate [Alopaeus2006]; four moments: the Lagrange weights of x_{p-1} .. x_{p+2}, which
// keep x³ as well. With rate λ K it shatters both partners into x_i + x_j
// monomers, which is exact on any grid (x_1 = 1). So, summing over unordered pairs i ≤ j with
// w_ij = K(x_i, x_j) (½ K(x_i, x_i) on the diagonal),
//   dN/dt = Σ_{i≤j} w_ij N_i N_j V_ij,
//   V_ij  = Σ_m w_m e_m - (1 + λ)(e_i + e_j) + λ (x_i + x_j) e_1.
// The section–section gain terms are the first sum of V_ij: class m gains from every pair whose sum lands
// within its stencil, weighted by its share. On integer pivots v is a pivot, it lands there whole, and
// this is the discrete equation of solvers/model.hpp term by term: the loss -(1+λ) N_k Σ_j K_kj N_j, the
// gain ½ Σ_{i+j=k} K_ij N_i N_j and the monomer gain λ N_1 Σ_{j≥2} x_j K_1j N_j + (λ/2) Σ_{i,j≥2}
// (x_i + x_j) K_ij N_i N_j (for i = j = 1, V = e_2 - 2e_1: shattering two monomers changes nothing).
// Truncation keeps its meaning: under `drop` an aggregate with v > N leaves (its mass is the leak),
// under `cutoff` pairs with v > N do not collide (w = 0). Σ_i x_i V_ij = 0 for every pair that stays on
// the grid, so mass is conserved exactly (to round-off) under cutoff, and under drop up to the leak.
//
// The loss is evaluated as r + λ r, never as (1 + λ) r: at the λ ≲ 1e-12 of the oscillation boundary near
// a = 1/2, 1 + λ rounds λ by up to 1 % (λ is a few ulp of 1), the same bias in every term.
//
// The form is bilinear in N, so J v = Σ_{i≤j} w_ij (N_i v_j + N_j v_i) V_ij exactly. Cost O(M²) per
// evaluation with the pair table (stencil, shares, weight) stored: M is a few hundred to a few thousand
// on a graded grid, where M² pair sums beat the FFT path's O(N log N) over all N sizes by orders of
// magnitude (N reaches 2^62).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>

#include "analysis/input_error.hpp"
#include "solvers/discretisation.hpp"

namespace aggkit {

namespace {

// The pairs (i ≤ j) of the classes with their collision weights and the stencils their aggregates land on:
// built once per discretisation, shared by its rates objects and its dense Jacobian.
class PairTable {
 public:
  explicit PairTable(const AggregationModel& model, const std::vector<double>& x)
      : x_(x), cutoff_(model.truncation == Truncation::cutoff) {
    const std::size_t M = x_.size();
    if (M > max_classes)
      throw InputError("grid", model.grid.describe() + " on N = " + std::to_string(model.size) + " (" +
                                   std::to_string(M) + " classes)",
                       "at most " + std::to_string(max_classes) + " size classes (raise grid.ratio or lower grid.resolved)");
    pairs_.reserve(M * (M + 1) / 2);
    const double N = x_.back();
    for (std::size_t i = 0; i < M; ++i)
      for (std::size_t j = i; j < M; ++j) pairs_.push_back(pair_of(model, i, j, N));
    // Pairs that leave the grid are those with x_i + x_j > N: for each i, the j from leak_start_[i] on.
    leak_start_.assign(M, M);
    row_.assign(M, 0);
    for (std::size_t i = 0, at = 0; i < M; at += M - i, ++i) {
      row_[i] = at;
      for (std::size_t j = M; j > i && pairs_[at + (j - 1 - i)].target() == M; --j) leak_start_[i] = j - 1;
    }
  }

  static constexpr std::size_t max_classes = 6000;

  std::size_t size() const { return x_.size(); }

  double leak_rate(std::span<const double> n) const {
    if (cutoff_) return 0.0;
    const std::size_t M = x_.size();
    double leak = 0.0;
    for (std::size_t i = 0; i < M; ++i)
      for (std::size_t j = leak_start_[i]; j < M; ++j)
        leak += (x_[i] + x_[j]) * pairs_[row_[i] + (j - i)].weight * n[i] * n[j];
    return leak;
  }

  // Row-major M×M Jacobian ∂f_k/∂N_l.
  void dense(double lambda, std::span<const double> n, std::span<double> jacobian) const {
    const std::size_t M = x_.size();
    std::fill(jacobian.begin(), jacobian.end(), 0.0);
    for_each_entry(lambda, n, [&](std::size_t row, std::size_t column, double value) { jacobian[row * M + column] += value; });
  }

  // ∂(leak rate)/∂N_l (drop; 0 under cutoff).
  void leak_gradient(std::span<const double> n, std::span<double> gradient) const {
    std::fill(gradient.begin(), gradient.end(), 0.0);
    if (cutoff_) return;
    const std::size_t M = x_.size();
    const Pair* pair = pairs_.data();
    for (std::size_t i = 0; i < M; ++i)
      for (std::size_t j = i; j < M; ++j, ++pair)
        if (pair->target() == M) {
          const double c = (x_[i] + x_[j]) * pair->weight;
          gradient[i] += c * n[j];
          gradient[j] += c * n[i];
        }
  }

  // out += scale Σ_{i≤j} w_ij (u_i v_j + u_j v_i) V_ij.
  void accumulate(double lambda, std::span<const double> u, std::span<const double> v, std::span<double> out,
                  double scale) const {
    const std::size_t M = x_.size();
    const Pair* pair = pairs_.data();
    double monomers = 0.0;
    for (std::size_t i = 0; i < M; ++i) {
      const double ui = u[i], vi = v[i], xi = x_[i];
      double lost_i = 0.0;
      for (std::size_t j = i; j < M; ++j, ++pair) {
        const double r = scale * pair->weight * (ui * v[j] + u[j] * vi);
        if (r == 0.0) continue;
        lost_i += r;
        out[j] -= r + lambda * r;
        monomers += (xi + x_[j]) * r;
        const std::size_t p = pair->target();
        if (p < M) {
          const std::uint32_t count = pair->count();
          for (std::uint32_t m = 0; m + 1 < count; ++m) out[p + m] += pair->share[m] * r;
          out[p + count - 1] += pair->share_at(count - 1) * r;  // 1 - the others: number exact
        }
      }
      out[i] -= lost_i + lambda * lost_i;
    }
    out[0] += lambda * monomers;
  }

  // Calls add(row, column, ∂f_row/∂N_column contribution) for every nonzero contribution.
  template <class Add>
  void for_each_entry(double lambda, std::span<const double> n, Add&& add) const {
    const std::size_t M = x_.size();
    const Pair* pair = pairs_.data();
    for (std::size_t i = 0; i < M; ++i)
      for (std::size_t j = i; j < M; ++j, ++pair) {
        if (pair->weight == 0.0) continue;
        // ∂(w N_i N_j)/∂N_i = w N_j and ∂/∂N_j = w N_i (both 2 w N_i on the diagonal).
        for (int side = 0; side < 2; ++side) {
          const std::size_t column = side == 0 ? i : j;
          const double d = pair->weight * (side == 0 ? n[j] : n[i]);
          if (d == 0.0) continue;
          add(i, column, -(d + lambda * d));
          add(j, column, -(d + lambda * d));
          add(0, column, lambda * (x_[i] + x_[j]) * d);
          const std::size_t p = pair->target();
          if (p < M)
            for (std::uint32_t m = 0; m < pair->count(); ++m) add(p + m, column, pair->share_at(m) * d);
        }
      }
  }

 private:
  // 40 bytes: the table is streamed twice per Newton-Krylov step (f and J v) and holds M²/2 pairs, ~24 MB at
  // M = 1100, beyond the caches; the stencil's last share is 1 - the others (Σ w_m = 1 is one of the
  // conditions that define them, and number stays exact to round-off), the stencil's first pivot and its
  // size are one word.
  struct Pair {
    double weight = 0.0;                // w_ij
    double share[3] = {1.0, 0.0, 0.0};  // the parts of the aggregate given to pivots target() .. target() + 2
    std::uint32_t stencil = 1;          // target() << 3 | count()
    std::size_t target() const { return stencil >> 3; }  // the first pivot of the stencil (M: beyond N)
    std::uint32_t count() const { return stencil & 7; }   // pivots in the stencil (1 to 4)
    double share_at(std::uint32_t m) const {
      if (m + 1 < count()) return share[m];
      double rest = 1.0;
      for (std::uint32_t l = 0; l < m; ++l) rest -= share[l];
      return rest;
    }
  };
  static_assert(sizeof(Pair) == 40);

  Pair pair_of(const AggregationModel& model, std::size_t i, std::size_t j, double N) const {
    const std::size_t M = x_.size();
    const double v = x_[i] + x_[j];
    Pair pair;
    pair.weight = (i == j ? 0.5 : 1.0) * model.kernel.at(x_[i], x_[j]);
    if (v > N) {
      pair.stencil = std::uint32_t(M) << 3;  // leaves the grid (drop) or does not collide (cutoff)
      if (cutoff_) pair.weight = 0.0;
      return pair;
    }
    const PivotShare share = pivot_share(x_, v, model.grid.scheme, model.grid.resolved);
    pair.stencil = std::uint32_t(share.first) << 3 | std::uint32_t(share.count);
    for (int m = 0; m + 1 < share.count; ++m) pair.share[m] = share.weight[m];
    return pair;
  }

  std::vector<double> x_;
  bool cutoff_;
  std::vector<Pair> pairs_;
  std::vector<std::size_t> row_;         // index in pairs_ of (i, i)
  std::vector<std::size_t> leak_start_;  // first j ≥ i whose pair (i, j) leaves the grid (M: none)
};

class SectionalRates final : public Rates {
 public:
  SectionalRates(std::shared_ptr<const PairTable> table, ShatteringRate lambda, GridScheme scheme)
      : Rates(table->size()), table_(std::move(table)), lambda_(std::move(lambda)), scheme_(scheme) {}

  void evaluate(double t, std::span<const double> n, std::span<double> dndt) override {
    std::fill(dndt.begin(), dndt.end(), 0.0);
    table_->accumulate(lambda_(t), n, n, dndt, 0.5);  // ½ Σ w (n_i n_j + n_j n_i) = Σ w n_i n_j
  }

  double leak_rate(double, std::span<const double> n) override { return table_->leak_rate(n); }

  void jacobian_times(double t, std::span<const double> n, std::span<const double> v, std::span<double> Jv) override {
    std::fill(Jv.begin(), Jv.end(), 0.0);
    table_->accumulate(lambda_(t), n, v, Jv, 1.0);
  }

  void jacobian_monomer_coupling(double t, std::span<const double> n, MonomerCoupling& J) override {
    const std::size_t M = size_;
    for (auto* v : {&J.diagonal, &J.subdiagonal, &J.monomer_column}) v->assign(M, 0.0);
    table_->for_each_entry(lambda_(t), n, [&](std::size_t row, std::size_t column, double value) {
      if (column == 0 && row >= 1) J.monomer_column[row] += value;
      else if (row == column) J.diagonal[row] += value;
      else if (row == column + 1) J.subdiagonal[row] += value;
    });
  }

  std::string describe() const override { return std::string(scheme_name(scheme_)) + " sections, O(M^2), M = " + std::to_string(size_); }

 private:
  std::shared_ptr<const PairTable> table_;
  ShatteringRate lambda_;
  GridScheme scheme_;
};

// The graded grid as a discretisation: its pair table built on first use and shared from then on.
class GradedGrid final : public Discretisation {
 public:
  explicit GradedGrid(const AggregationModel& model) : Discretisation(model, grid_pivots(model.grid, model.size)) {
    if (unknowns() > PairTable::max_classes) table();  // refuse an over-long grid at once, with its message
  }

  std::unique_ptr<Rates> rates(RatesPath, double, double) const override {
    return std::make_unique<SectionalRates>(table(), model_.lambda, model_.grid.scheme);
  }
  void dense_jacobian(double t, std::span<const double> n, std::span<double> jacobian) const override {
    table()->dense(model_.lambda(t), n, jacobian);
  }
  void leak_gradient(double, std::span<const double> n, std::span<double> gradient) const override {
    table()->leak_gradient(n, gradient);
  }
  bool dense_solves() const override { return true; }
  std::vector<double> carry(std::span<const double> from, std::span<const double> state) const override {
    if (!from.empty()) return regrid(from, state, sizes_);
    std::vector<double> integers(state.size());
    for (std::size_t k = 0; k < integers.size(); ++k) integers[k] = double(k + 1);
    return regrid(integers, state, sizes_);
  }
  std::vector<double> output_sizes() const override { return sizes_; }

 private:
  std::shared_ptr<const PairTable> table() const {
    std::call_once(built_, [&] { table_ = std::make_shared<const PairTable>(model_, sizes_); });
    return table_;
  }
  mutable std::once_flag built_;
  mutable std::shared_ptr<const PairTable> table_;
};

}  // namespace

std::unique_ptr<Discretisation> make_graded_discretisation(const AggregationModel& model) {
  return std::make_unique<GradedGrid>(model);
}

}  // namespace aggkit

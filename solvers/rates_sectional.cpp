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
// magnitude (N reaches 2^62). For a kernel with exact factors, the pairs whose aggregate stays inside the
// larger partner's interval (three quarters of them on the scan's grid) are summed in O(M) through those
// factors instead (solvers/sectional_far_field.hpp); the pair loop keeps the near band and the grid's top.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <utility>

#include "analysis/input_error.hpp"
#include "solvers/discretisation.hpp"
#include "solvers/sectional_far_field.hpp"

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
    const std::size_t P = M * (M + 1) / 2;
    weight_.reserve(P);
    stencil_.reserve(P);
    for (auto& s : share_) s.reserve(P);
    const double N = x_.back();
    for (std::size_t i = 0; i < M; ++i)
      for (std::size_t j = i; j < M; ++j) add_pair(model, i, j, N);
    // Pairs that leave the grid are those with x_i + x_j > N: for each i, the j from leak_start_[i] on.
    leak_start_.assign(M, M);
    row_.assign(M, 0);
    for (std::size_t i = 0, at = 0; i < M; at += M - i, ++i) {
      row_[i] = at;
      for (std::size_t j = M; j > i && target(at + (j - 1 - i)) == M; --j) leak_start_[i] = j - 1;
    }
    near_end_.assign(M, M);
    near_top_ = M;
    if (const Kernel::Factors* factors = model.kernel.exact_factors(); factors && M >= 3) build_far_field(*factors);
    build_runs();
  }

  // Pairs summed by the far field rather than one by one (0 without an exact kernel factorisation).
  std::size_t far_pairs() const { return far_ ? far_->pairs() : 0; }

  static constexpr std::size_t max_classes = 6000;
  static constexpr std::size_t max_stencil = 4;

  std::size_t size() const { return x_.size(); }

  double leak_rate(std::span<const double> n) const {
    if (cutoff_) return 0.0;
    const std::size_t M = x_.size();
    double leak = 0.0;
    for (std::size_t i = 0; i < M; ++i)
      for (std::size_t j = leak_start_[i]; j < M; ++j) leak += (x_[i] + x_[j]) * weight_[row_[i] + (j - i)] * n[i] * n[j];
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
    for (std::size_t i = 0; i < M; ++i)
      for (std::size_t j = leak_start_[i]; j < M; ++j) {
        const double c = (x_[i] + x_[j]) * weight_[row_[i] + (j - i)];
        gradient[i] += c * n[j];
        gradient[j] += c * n[i];
      }
  }

  // What accumulate works in: the pair rates of one row, and the output padded by a stencil's width, so that a
  // run's every stencil can be taken as wide as its widest (the unused shares are 0) up to the grid's end.
  struct Scratch {
    std::vector<double> rate, out;
    SectionalFarField::Scratch far;
  };

  // out += scale Σ_{i≤j} w_ij (u_i v_j + u_j v_i) V_ij. Row by row in two passes: the rates, losses and
  // monomer gain (a loop without indirection), then the gains run by run and share by share. Within a run
  // the stencils move on by one pivot per pair, so each share's adds go to consecutive entries: a vector
  // loop, where one pass writing each stencil's entries in turn chains every add to the last pair's store to
  // the same entry.
  void accumulate(double lambda, std::span<const double> u, std::span<const double> v, std::span<double> out,
                  double scale, Scratch& scratch) const {
    const std::size_t M = x_.size();
    scratch.rate.resize(M);
    scratch.out.assign(M + max_stencil, 0.0);
    double* gain = scratch.out.data();
    double* __restrict rate = scratch.rate.data();
    double monomers = 0.0;
    for (std::size_t i = 0; i < M; ++i) {
      const std::size_t at = row_[i];
      const double ui = u[i], vi = v[i], xi = x_[i];
      const double* __restrict w = weight_.data() + at;
      const double* __restrict xj = x_.data() + i;
      const double* __restrict uj = u.data() + i;
      const double* __restrict vj = v.data() + i;
      double* loss = gain + i;
      double lost_i = 0.0;
      // The row's near pairs: columns i .. near_end_ − 1 and near_top_ .. M − 1 (the far ones between them
      // are the far field's).
      const auto [first_end, second_begin] = near_segments(i);
      for (const auto& [l0, l1] : {std::pair{std::size_t(0), first_end - i}, std::pair{second_begin - i, M - i}})
        for (std::size_t l = l0; l < l1; ++l) {
          const double r = scale * w[l] * (ui * vj[l] + uj[l] * vi);
          rate[l] = r;
          loss[l] -= r + lambda * r;
          lost_i += r;
          monomers += (xi + xj[l]) * r;
        }
      gain[i] -= lost_i + lambda * lost_i;
      for (std::size_t k = run_row_[i]; k < run_row_[i + 1]; ++k) {
        const Run& run = runs_[k];
        double* __restrict to = gain + (std::ptrdiff_t(i) + run.offset);  // entry of pair l's stencil: to[l]
        for (std::uint32_t m = 0; m < run.count; ++m) {
          const double* __restrict share = share_[m].data() + at;
          for (std::uint32_t l = run.begin; l < run.end; ++l) to[l + m] += share[l] * rate[l];
        }
      }
    }
    if (far_) far_->accumulate(lambda, u, v, scale, gain, monomers, scratch.far);
    gain[0] += lambda * monomers;
    for (std::size_t k = 0; k < M; ++k) out[k] += gain[k];
  }

  // Calls add(row, column, ∂f_row/∂N_column contribution) for every nonzero contribution.
  template <class Add>
  void for_each_entry(double lambda, std::span<const double> n, Add&& add) const {
    const std::size_t M = x_.size();
    for (std::size_t i = 0, at = 0; i < M; ++i)
      for (std::size_t j = i; j < M; ++j, ++at) {
        const double weight = weight_[at];
        if (weight == 0.0) continue;
        // ∂(w N_i N_j)/∂N_i = w N_j and ∂/∂N_j = w N_i (both 2 w N_i on the diagonal).
        for (int side = 0; side < 2; ++side) {
          const std::size_t column = side == 0 ? i : j;
          const double d = weight * (side == 0 ? n[j] : n[i]);
          if (d == 0.0) continue;
          add(i, column, -(d + lambda * d));
          add(j, column, -(d + lambda * d));
          add(0, column, lambda * (x_[i] + x_[j]) * d);
          const std::size_t p = target(at);
          if (p < M)
            for (std::uint32_t m = 0; m < (stencil_[at] & 7); ++m) add(p + m, column, share_[m][at] * d);
        }
      }
  }

 private:
  // Structure of arrays over the pairs (i, j ≥ i) row by row, so that accumulate's passes each stream one: the
  // weight w_ij, the stencil (its first pivot << 3 | its size, 1 to 4; first pivot M: beyond N) and the
  // shares given to pivots first .. first + 3 (0 beyond the stencil). The stencil's last share is 1 - the
  // others (Σ w_m = 1 is one of the conditions that define them, and number stays exact to round-off).
  std::size_t target(std::size_t at) const { return stencil_[at] >> 3; }

  // A run of pairs (i, i + l), l in [begin, end), whose stencils start at pivot i + l + offset: the row's
  // pairs that stay on the grid, cut where the offset changes; count is the widest stencil in the run.
  struct Run {
    std::uint32_t begin, end;
    std::int32_t offset;
    std::uint32_t count;
  };

  void build_runs() {
    const std::size_t M = x_.size();
    run_row_.assign(M + 1, 0);
    for (std::size_t i = 0; i < M; ++i) {
      run_row_[i] = runs_.size();
      const auto [first_end, second_begin] = near_segments(i);
      for (std::size_t l = 0; i + l < leak_start_[i]; ++l) {
        if (i + l == first_end && second_begin > first_end) l = second_begin - i;  // over the far pairs
        if (i + l >= leak_start_[i]) break;
        const std::size_t at = row_[i] + l;
        const std::int32_t offset = std::int32_t(target(at)) - std::int32_t(i + l);
        const std::uint32_t count = stencil_[at] & 7;
        if (runs_.size() > run_row_[i] && runs_.back().offset == offset && runs_.back().end == l) {
          runs_.back().end = std::uint32_t(l + 1);
          runs_.back().count = std::max(runs_.back().count, count);
        } else {
          runs_.push_back(Run{std::uint32_t(l), std::uint32_t(l + 1), offset, count});
        }
      }
    }
    run_row_[M] = runs_.size();
  }

  // Row i's near pairs: columns [i, first_end) and [second_begin, M) (one range where second_begin = first_end).
  std::pair<std::size_t, std::size_t> near_segments(std::size_t i) const {
    const std::size_t M = x_.size();
    if (near_end_[i] >= near_top_) return {M, M};
    return {near_end_[i], near_top_};
  }

  // The far field (solvers/sectional_far_field.hpp): column j's partners i < I_j whose pairs stay within
  // (x_j, x_{j+1}) on one stencil with the stored shares equal, to 1e-12, to its Lagrange polynomials. I_j is
  // made nondecreasing (the smallest I over the columns above it), up to a top column near_top_ chosen to keep
  // the most far pairs; the columns from near_top_ on (the grid's end, where the last intervals may be
  // short) stay near. Row i's far pairs are then the columns from near_end_[i] to near_top_ − 1.
  void build_far_field(const Kernel::Factors& factors) {
    const std::size_t M = x_.size();
    far_ = std::make_unique<SectionalFarField>(x_, factors);
    std::vector<std::uint32_t> raw(M, 0);
    for (std::size_t j = 1; j + 1 < M; ++j) raw[j] = std::uint32_t(far_partners(j));
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
    near_top_ = best_top;
    for (std::size_t i = 0, j = 0; i < M; ++i) {
      while (j < near_top_ && count[j] <= i) ++j;
      near_end_[i] = j;  // the first column with i among its far partners (near_top_: none)
    }
    far_->set_counts(std::move(count));
  }

  // How many partners i = 0, 1, ... of column j (i < j) the far field can take: their aggregates stay below
  // x_{j+1}, on pair (0, j)'s stencil, with the shares its polynomials give.
  std::size_t far_partners(std::size_t j) {
    const std::size_t M = x_.size();
    const std::uint32_t stencil = stencil_[row_[0] + j];
    const std::size_t first = stencil >> 3, width = stencil & 7;
    if (first >= M || width == 0 || !(x_[0] + x_[j] < x_[j + 1])) return 0;
    far_->set_stencil(j, first, width);
    std::size_t i = 0;
    for (; i < j; ++i) {
      const std::size_t at = row_[i] + (j - i);
      if (!(x_[i] + x_[j] < x_[j + 1]) || stencil_[at] != stencil || weight_[at] == 0.0) break;
      bool same = true;
      for (std::size_t m = 0; m < width; ++m) same = same && std::abs(share_[m][at] - far_->share(j, m, x_[i])) <= 1e-12;
      if (!same) break;
    }
    return i;
  }

  void add_pair(const AggregationModel& model, std::size_t i, std::size_t j, double N) {
    const std::size_t M = x_.size();
    const double v = x_[i] + x_[j];
    double weight = (i == j ? 0.5 : 1.0) * model.kernel.at(x_[i], x_[j]);
    double shares[max_stencil] = {0.0, 0.0, 0.0, 0.0};
    std::uint32_t stencil = std::uint32_t(M) << 3;  // leaves the grid (drop) or does not collide (cutoff)
    if (v > N) {
      if (cutoff_) weight = 0.0;
    } else {
      const PivotShare share = pivot_share(x_, v, model.grid.scheme, model.grid.resolved);
      stencil = std::uint32_t(share.first) << 3 | std::uint32_t(share.count);
      double rest = 1.0;
      for (int m = 0; m + 1 < share.count; ++m) rest -= shares[m] = share.weight[m];
      shares[share.count - 1] = rest;
    }
    weight_.push_back(weight);
    stencil_.push_back(stencil);
    for (std::size_t m = 0; m < max_stencil; ++m) share_[m].push_back(shares[m]);
  }

  std::vector<double> x_;
  bool cutoff_;
  std::vector<double> weight_;
  std::vector<std::uint32_t> stencil_;
  std::vector<double> share_[max_stencil];
  std::vector<std::size_t> row_;         // index of (i, i) in the pair arrays
  std::vector<std::size_t> leak_start_;  // first j ≥ i whose pair (i, j) leaves the grid (M: none)
  std::vector<Run> runs_;                // row by row
  std::unique_ptr<SectionalFarField> far_;  // null: every pair near
  std::vector<std::size_t> near_end_;    // row i: its near pairs end at column near_end_[i] ...
  std::size_t near_top_ = 0;             // ... and resume at this column
  std::vector<std::size_t> run_row_;     // row i's runs: runs_[run_row_[i]] .. runs_[run_row_[i + 1] - 1]
};

class SectionalRates final : public Rates {
 public:
  SectionalRates(std::shared_ptr<const PairTable> table, ShatteringRate lambda, GridScheme scheme)
      : Rates(table->size()), table_(std::move(table)), lambda_(std::move(lambda)), scheme_(scheme) {}

  void evaluate(double t, std::span<const double> n, std::span<double> dndt) override {
    std::fill(dndt.begin(), dndt.end(), 0.0);
    table_->accumulate(lambda_(t), n, n, dndt, 0.5, scratch_);  // ½ Σ w (n_i n_j + n_j n_i) = Σ w n_i n_j
  }

  double leak_rate(double, std::span<const double> n) override { return table_->leak_rate(n); }

  void jacobian_times(double t, std::span<const double> n, std::span<const double> v, std::span<double> Jv) override {
    std::fill(Jv.begin(), Jv.end(), 0.0);
    table_->accumulate(lambda_(t), n, v, Jv, 1.0, scratch_);
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

  std::string describe() const override {
    std::string text = std::string(scheme_name(scheme_)) + " sections, O(M^2), M = " + std::to_string(size_);
    if (const std::size_t far = table_->far_pairs(); far > 0)
      text += "; " + std::to_string(far) + " of " + std::to_string(size_ * (size_ + 1) / 2) + " pairs summed as a separable far field";
    return text;
  }

 private:
  std::shared_ptr<const PairTable> table_;
  ShatteringRate lambda_;
  GridScheme scheme_;
  PairTable::Scratch scratch_;
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

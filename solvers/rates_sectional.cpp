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
// evaluation with the pair table (stencil, shares, weight) stored (solvers/sectional_pairs.hpp, in runs
// along the near band's diagonals that are vector loops): M is a few hundred to a few thousand
// on a graded grid, where M² pair sums beat the FFT path's O(N log N) over all N sizes by orders of
// magnitude (N reaches 2^62). For a kernel with exact factors, the pairs whose aggregate stays inside the
// larger partner's interval (three quarters of them on the scan's grid) are summed in O(M) through those
// factors instead (solvers/sectional_far_field.hpp); the pair loop keeps the near band and the grid's top.
#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <utility>

#include "analysis/input_error.hpp"
#include "solvers/discretisation.hpp"
#include "solvers/sectional_pairs.hpp"

namespace aggkit {

namespace {

class SectionalRates final : public Rates {
 public:
  SectionalRates(std::shared_ptr<const SectionalPairs> table, ShatteringRate lambda, GridScheme scheme)
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
    for (auto* v : {&J.diagonal, &J.subdiagonal, &J.monomer_column}) v->resize(size_);
    table_->monomer_coupling(lambda_(t), n, J.diagonal, J.subdiagonal, J.monomer_column);
  }

  std::string describe() const override {
    std::string text = std::string(scheme_name(scheme_)) + " sections, O(M^2), M = " + std::to_string(size_);
    if (const std::size_t far = table_->far_pairs(); far > 0)
      text += "; " + std::to_string(far) + " of " + std::to_string(size_ * (size_ + 1) / 2) + " pairs summed as a separable far field";
    return text;
  }

 private:
  std::shared_ptr<const SectionalPairs> table_;
  ShatteringRate lambda_;
  GridScheme scheme_;
  SectionalPairs::Scratch scratch_;
};

// The graded grid as a discretisation: its pair table built on first use and shared from then on.
class GradedGrid final : public Discretisation {
 public:
  explicit GradedGrid(const AggregationModel& model) : Discretisation(model, grid_pivots(model.grid, model.size)) {
    if (unknowns() > SectionalPairs::max_classes) table();  // refuse an over-long grid at once, with its message
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
  std::shared_ptr<const SectionalPairs> table() const {
    std::call_once(built_, [&] { table_ = std::make_shared<const SectionalPairs>(model_, sizes_); });
    return table_;
  }
  mutable std::once_flag built_;
  mutable std::shared_ptr<const SectionalPairs> table_;
};

}  // namespace

std::unique_ptr<Discretisation> make_graded_discretisation(const AggregationModel& model) {
  return std::make_unique<GradedGrid>(model);
}

}  // namespace aggkit

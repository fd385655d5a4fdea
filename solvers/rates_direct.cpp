// Direct O(N^2) evaluation of the aggregation-shattering right-hand side, written term by term as the
// equations of solvers/model.hpp: the mass-conserving form of [Kalinov2022, eq. 4], with the factor 1/2 on
// the monomer double sum that the printed equation lacks. It is the oracle the fast path is tested
// against, so it deliberately shares no algebra with rates_fast.cpp.
#include <cmath>
#include <stdexcept>
#include <vector>

#include "analysis/input_error.hpp"
#include "solvers/discretisation.hpp"

namespace aggkit {

RatesPath rates_path_from_name(const std::string& name) {
  if (name == "fast") return RatesPath::fast;
  if (name == "direct") return RatesPath::direct;
  throw InputError("rhs", "\"" + name + "\"", "one of fast, direct");
}

std::string to_string(RatesPath p) { return p == RatesPath::fast ? "fast" : "direct"; }

namespace {

constexpr std::size_t stored_matrix_limit = 6144;  // N above which K_ij is recomputed on the fly

class DirectRates final : public Rates {
 public:
  explicit DirectRates(const AggregationModel& model)
      : Rates(model.size), model_(model), cutoff_(model.truncation == Truncation::cutoff) {
    if (size_ <= stored_matrix_limit) {
      matrix_.resize(size_ * size_);
      for (std::size_t i = 1; i <= size_; ++i)
        for (std::size_t j = 1; j <= size_; ++j) matrix_[(i - 1) * size_ + (j - 1)] = model_.kernel(i, j);
    }
  }

  void evaluate(double t, std::span<const double> n, std::span<double> dndt) override {
    std::fill(dndt.begin(), dndt.end(), 0.0);
    bilinear(t, n, n, dndt);
  }

  double leak_rate(double, std::span<const double> n) override {
    if (cutoff_) return 0.0;
    double leak = 0.0;  // ½ Σ_{i,j ≤ N, i+j > N} (i+j) K_ij n_i n_j
    for (std::size_t i = 1; i <= size_; ++i)
      for (std::size_t j = size_ - i + 1; j <= size_; ++j)
        leak += 0.5 * double(i + j) * K(i, j) * n[i - 1] * n[j - 1];
    return leak;
  }

  void jacobian_times(double t, std::span<const double> n, std::span<const double> v,
                      std::span<double> Jv) override {
    std::fill(Jv.begin(), Jv.end(), 0.0);
    bilinear(t, n, v, Jv);  // f(n) = B(n, n)  ⇒  J v = B(n, v) + B(v, n)
    bilinear(t, v, n, Jv);
  }

  void jacobian_monomer_coupling(double t, std::span<const double> n, MonomerCoupling& J) override {
    // ∂f_k/∂n_k = -(1+λ)(Σ_j K_kj n_j + K_kk n_k) for k ≥ 2 (the gain term has no n_k); for monomers
    // also + λ Σ_{j≥2} j K_1j n_j. ∂f_k/∂n_1 = K_{1,k-1} n_{k-1} - (1+λ) n_k K_k1 (k ≥ 2);
    // ∂f_k/∂n_{k-1} = K_{k-1,1} n_1 - (1+λ) n_k K_{k,k-1} (k ≥ 3).
    const double lambda = model_.lambda(t);
    for (auto* v : {&J.diagonal, &J.subdiagonal, &J.monomer_column}) v->assign(size_, 0.0);
    for (std::size_t k = 1; k <= size_; ++k) {
      double rate = 0.0;
      for (std::size_t j = 1; j <= size_; ++j) rate += K(k, j) * n[j - 1];
      const double loss_factor = k == 1 ? 1.0 : 1.0 + lambda;
      J.diagonal[k - 1] = -loss_factor * (rate + K(k, k) * n[k - 1]);
      if (k >= 2) J.monomer_column[k - 1] = K(1, k - 1) * n[k - 2] - loss_factor * n[k - 1] * K(k, 1);
      if (k >= 3) J.subdiagonal[k - 1] = K(k - 1, 1) * n[0] - loss_factor * n[k - 1] * K(k, k - 1);
    }
    for (std::size_t j = 2; j <= size_; ++j) J.diagonal[0] += lambda * double(j) * K(1, j) * n[j - 1];
  }

  std::string describe() const override { return "direct O(N^2)"; }

 private:
  double K(std::size_t i, std::size_t j) const {
    if (cutoff_ && i + j > size_) return 0.0;  // cutoff truncation: no collisions that would exceed N
    return matrix_.empty() ? model_.kernel(i, j) : matrix_[(i - 1) * size_ + (j - 1)];
  }

  // out += B(x, y), the bilinear form with B(n, n) = dn/dt.
  void bilinear(double t, std::span<const double> x, std::span<const double> y, std::span<double> out) const {
    const double lambda = model_.lambda(t);
    const std::size_t N = size_;
    // Aggregation gain, k ≥ 2: (1/2) Σ_{i+j=k} K_ij x_i y_j.
    for (std::size_t k = 2; k <= N; ++k) {
      double gain = 0.0;
      for (std::size_t i = 1; i < k; ++i) gain += K(i, k - i) * x[i - 1] * y[k - i - 1];
      out[k - 1] += 0.5 * gain;
    }
    // Loss by aggregation and shattering: -(1+λ) x_k Σ_j K_kj y_j (k ≥ 2), -x_1 Σ_j K_1j y_j.
    for (std::size_t k = 1; k <= N; ++k) {
      double rate = 0.0;
      for (std::size_t j = 1; j <= N; ++j) rate += K(k, j) * y[j - 1];
      out[k - 1] -= (k == 1 ? 1.0 : 1.0 + lambda) * x[k - 1] * rate;
    }
    if (lambda == 0.0) return;
    // Monomers from shattering: λ x_1 Σ_{j≥2} j K_1j y_j + (λ/2) Σ_{i,j≥2} (i+j) K_ij x_i y_j.
    double with_monomer = 0.0, between_aggregates = 0.0;
    for (std::size_t j = 2; j <= N; ++j) with_monomer += double(j) * K(1, j) * y[j - 1];
    for (std::size_t i = 2; i <= N; ++i)
      for (std::size_t j = 2; j <= N; ++j) between_aggregates += double(i + j) * K(i, j) * x[i - 1] * y[j - 1];
    out[0] += lambda * x[0] * with_monomer + 0.5 * lambda * between_aggregates;
  }

  AggregationModel model_;  // a copy: the rates may outlive the discretisation that made them
  bool cutoff_;
  std::vector<double> matrix_;
};

}  // namespace

std::unique_ptr<Rates> make_direct_rates(const AggregationModel& model) {
  return std::make_unique<DirectRates>(model);
}

std::unique_ptr<Rates> make_rates(const AggregationModel& model, RatesPath path, double lowrank_tolerance,
                                  double jacobian_tolerance) {
  return make_discretisation(model)->rates(path, lowrank_tolerance, jacobian_tolerance);
}

}  // namespace aggkit

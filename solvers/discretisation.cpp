// The discretisation object (solvers/discretisation.hpp) and its uniform kind: every size 1..N a class.
#include "solvers/discretisation.hpp"

#include <algorithm>


namespace aggkit {

Discretisation::Discretisation(const AggregationModel& model, std::vector<double> sizes)
    : model_(model), sizes_(std::move(sizes)), widths_(pivot_widths(sizes_)) {}

std::vector<double> Discretisation::densities(std::span<const double> n) const {
  return section_densities(sizes_, n, model_.grid.scheme, model_.grid.resolved);
}

namespace {

class UniformGrid final : public Discretisation {
 public:
  explicit UniformGrid(const AggregationModel& model) : Discretisation(model, grid_pivots(model.grid, model.size)) {}

  std::unique_ptr<Rates> rates(RatesPath path, double lowrank_tolerance, double jacobian_tolerance) const override {
    return path == RatesPath::direct ? make_direct_rates(model_)
                                     : make_fast_rates(model_, lowrank_tolerance, jacobian_tolerance);
  }

  // J_kl = ∂f_k/∂n_l from differentiating the equations of solvers/model.hpp term by term.
  void dense_jacobian(double t, std::span<const double> n, std::span<double> jacobian) const override {
    const std::size_t N = model_.size;
    const double lambda = model_.lambda(t);
    const std::vector<double> K = kernel_matrix();
    auto Km = [&](std::size_t i, std::size_t j) { return K[(i - 1) * N + j - 1]; };
    std::vector<double> rate(N + 1, 0.0);
    for (std::size_t k = 1; k <= N; ++k)
      for (std::size_t j = 1; j <= N; ++j) rate[k] += Km(k, j) * n[j - 1];
    std::fill(jacobian.begin(), jacobian.end(), 0.0);
    auto J = [&](std::size_t k, std::size_t l) -> double& { return jacobian[(k - 1) * N + (l - 1)]; };
    for (std::size_t k = 1; k <= N; ++k) {
      const double loss_factor = k == 1 ? 1.0 : 1.0 + lambda;
      for (std::size_t l = 1; l < k; ++l) J(k, l) += Km(l, k - l) * n[k - l - 1];  // gain
      J(k, k) -= loss_factor * rate[k];
      for (std::size_t l = 1; l <= N; ++l) J(k, l) -= loss_factor * n[k - 1] * Km(k, l);
    }
    if (lambda == 0.0) return;
    // Monomer row: λ n_1 Σ_{j≥2} j K_1j n_j + (λ/2) Σ_{i,j≥2} (i+j) K_ij n_i n_j.
    double with_monomer = 0.0;
    for (std::size_t j = 2; j <= N; ++j) with_monomer += double(j) * Km(1, j) * n[j - 1];
    J(1, 1) += lambda * with_monomer;
    for (std::size_t l = 2; l <= N; ++l) {
      double d = double(l) * Km(1, l) * n[0];
      for (std::size_t i = 2; i <= N; ++i) d += double(i + l) * Km(i, l) * n[i - 1];
      J(1, l) += lambda * d;
    }
  }

  // ∂(leak rate)/∂n_l = Σ_{j > N-l} (l+j) K_lj n_j under drop (0 under cutoff); O(N²).
  void leak_gradient(double, std::span<const double> n, std::span<double> gradient) const override {
    const std::size_t N = model_.size;
    std::fill(gradient.begin(), gradient.end(), 0.0);
    if (model_.truncation == Truncation::cutoff) return;
    for (std::size_t l = 1; l <= N; ++l)
      for (std::size_t j = N - l + 1; j <= N; ++j) gradient[l - 1] += double(l + j) * model_.kernel(l, j) * n[j - 1];
  }

  bool dense_solves() const override { return false; }

  // From integer sizes: cut to N, or extended by the tail fit (extend_steady_state); from a graded grid's
  // classes: regrid.
  std::vector<double> carry(std::span<const double> from, std::span<const double> state) const override {
    const std::size_t N = model_.size;
    if (!from.empty()) return regrid(from, state, sizes_);
    if (state.size() >= N) return {state.begin(), state.begin() + std::ptrdiff_t(N)};
    return extend_steady_state(state, N);
  }

  std::vector<double> output_sizes() const override { return {}; }

 private:
  // K_ij (i, j = 1..N, row-major), 0 where cutoff truncation forbids the pair (i + j > N).
  std::vector<double> kernel_matrix() const {
    const std::size_t N = model_.size;
    const bool cutoff = model_.truncation == Truncation::cutoff;
    std::vector<double> K(N * N);
    for (std::size_t i = 1; i <= N; ++i)
      for (std::size_t j = 1; j <= N; ++j) K[(i - 1) * N + j - 1] = cutoff && i + j > N ? 0.0 : model_.kernel(i, j);
    return K;
  }
};

}  // namespace

std::unique_ptr<Discretisation> make_discretisation(const AggregationModel& model) {
  model.grid.validate();
  if (model.grid.uniform()) return std::make_unique<UniformGrid>(model);
  return make_graded_discretisation(model);
}

}  // namespace aggkit

#include "solvers/mass_constrained_system.hpp"

#include <algorithm>
#include <cmath>

#include "analysis/input_error.hpp"

namespace aggkit {

double total_mass(std::span<const double> n) {
  double mass = 0.0;
  for (std::size_t k = 0; k < n.size(); ++k) mass += double(k + 1) * n[k];
  return mass;
}

double total_mass(std::span<const double> n, std::span<const double> sizes) {
  double mass = 0.0;
  for (std::size_t k = 0; k < n.size(); ++k) mass += sizes[k] * n[k];
  return mass;
}

MassConstrainedSystem::MassConstrainedSystem(const AggregationModel& model, RatesPath path, double lowrank_tolerance)
    : grid_((model.validate(0.0), make_discretisation(model))), N_(grid_->unknowns()), mass_row_(N_ - 1),
      cutoff_(model.truncation == Truncation::cutoff), sizes_(grid_->sizes()) {
  if (!model.lambda.is_constant())
    throw InputError("lambda", model.lambda.describe(), "a constant shattering rate for a steady state");
  lambda_ = model.lambda(0.0);
  if (cutoff_) {
    if (N_ < 3) throw InputError("size", std::to_string(N_), "at least 3 for a cutoff steady state");
    mass_row_ = N_ - 2;
  }
  const std::vector<double> initial = grid_->initial_state();
  mass_ = total_mass(std::span<const double>(initial).first(mass_row_ + 1), sizes_);
  if (!(mass_ > 0.0))
    throw InputError("initial", "no mass below the absorbing size N",
                     "a cutoff steady state needs mass in sizes < N");
  rates_ = grid_->rates(path, lowrank_tolerance, 0.0);
  state_.assign(N_, 0.0);
  dndt_.assign(N_, 0.0);
  std::vector<double> F(N_);
  residual(initial, F);
  double norm = 0.0;
  for (double x : F) norm += x * x;
  residual_scale_ = std::sqrt(norm) > 0.0 ? std::sqrt(norm) : 1.0;
}

void MassConstrainedSystem::residual(std::span<const double> n, std::span<double> F) {
  rates_->evaluate(0.0, n, F);
  F[mass_row_] = total_mass(n.first(mass_row_ + 1), sizes_) - mass_;
  for (std::size_t k = mass_row_ + 1; k < N_; ++k) F[k] = n[k];
}

double MassConstrainedSystem::balance_scale(std::span<const double> n) {
  Rates::MonomerCoupling coupling;
  rates_->jacobian_monomer_coupling(0.0, n, coupling);
  double sum = 0.0;
  for (std::size_t k = 0; k < mass_row_; ++k) sum += coupling.diagonal[k] * n[k] * coupling.diagonal[k] * n[k];
  return std::sqrt(sum);
}

double MassConstrainedSystem::leak_rate(std::span<const double> n) {
  if (!cutoff_) return rates_->leak_rate(0.0, n);
  rates_->evaluate(0.0, n, dndt_);  // with n_N = 0, f_N is the gain of the absorbing class
  return sizes_[N_ - 1] * dndt_[N_ - 1];
}

void MassConstrainedSystem::dense_jacobian(std::span<const double> n, std::span<double> J) {
  const std::size_t N = N_;
  grid_->dense_jacobian(0.0, n, J);
  for (std::size_t k = 0; k < N; ++k) J[mass_row_ * N + k] = k <= mass_row_ ? sizes_[k] : 0.0;
  for (std::size_t r = mass_row_ + 1; r < N; ++r)
    for (std::size_t k = 0; k < N; ++k) J[r * N + k] = r == k ? 1.0 : 0.0;
}

void MassConstrainedSystem::set_state(std::span<const double> n) {
  std::copy(n.begin(), n.end(), state_.begin());
  rates_->jacobian_monomer_coupling(0.0, state_, coupling_);
}

void MassConstrainedSystem::apply(std::span<const double> v, std::span<double> out, double shift) {
  rates_->jacobian_times(0.0, state_, v, out);
  for (std::size_t k = 0; k < mass_row_; ++k) out[k] -= shift * v[k];
  out[mass_row_] = total_mass(v.first(mass_row_ + 1), sizes_);
  for (std::size_t k = mass_row_ + 1; k < N_; ++k) out[k] = v[k];
}

void MassConstrainedSystem::precondition(std::span<const double> r, std::span<double> z, double shift) const {
  const auto& D = coupling_.diagonal;
  const auto& S = coupling_.subdiagonal;
  const auto& C = coupling_.monomer_column;
  // A zero pivot (no collisions at all for that size, e.g. cutoff at k = N) falls back to the identity.
  auto pivot = [&](std::size_t k) {
    const double d = D[k] - shift;
    return d != 0.0 ? d : 1.0;
  };
  z[0] = r[0] / pivot(0);
  double mass = z[0];
  for (std::size_t k = 1; k < mass_row_; ++k) {
    z[k] = (r[k] - C[k] * z[0] - S[k] * z[k - 1]) / pivot(k);
    mass += sizes_[k] * z[k];
  }
  z[mass_row_] = (r[mass_row_] - mass) / sizes_[mass_row_];
  for (std::size_t k = mass_row_ + 1; k < N_; ++k) z[k] = r[k];
}

}  // namespace aggkit

#include "solvers/hopf_normal_form.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "analysis/input_error.hpp"
#include "solvers/discretisation.hpp"
#include "solvers/mass_constrained_system.hpp"
#include "solvers/mass_shell.hpp"
#include "solvers/rates.hpp"
#include "solvers/stability.hpp"

namespace aggkit {

namespace {

using Complex = std::complex<double>;

// The eigenvector of `A` for the eigenvalue nearest `mu` by inverse iteration on one LU of A − σI, σ a hair
// off μ (the Arnoldi value is accurate to ~1e-10, so each iteration gains ~10 digits).
Eigen::VectorXcd eigenvector(const Eigen::MatrixXcd& A, Complex mu) {
  const Eigen::Index n = A.rows();
  const Complex sigma = mu + Complex(1e-9, 1e-9) * std::abs(mu);
  const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(A - sigma * Eigen::MatrixXcd::Identity(n, n));
  Eigen::VectorXcd v(n);
  for (Eigen::Index k = 0; k < n; ++k) v[k] = Complex(1.0, 0.5 * double(k) / double(n));
  for (int iteration = 0; iteration < 3; ++iteration) {
    v = lu.solve(v);
    v.normalize();
  }
  return v;
}

// The second derivative B(u, v) of the rates on the mass shell: u, v on the m shell unknowns, lifted to the
// classes (class m keeps the mass), B = J(n + s U) V − J(n) V over s, exact for the quadratic rates; s makes
// s U as large as n itself, so the difference loses no digits to rounding.
class SecondDerivative {
 public:
  SecondDerivative(const Discretisation& grid, std::span<const double> n, std::size_t m)
      : grid_(grid), rates_(grid.rates()), n_(n.begin(), n.end()), m_(m) {
    for (double v : n_) top_ = std::max(top_, std::abs(v));
  }

  Eigen::VectorXcd operator()(const Eigen::VectorXcd& u, const Eigen::VectorXcd& v) {
    const Eigen::VectorXd ur = u.real(), ui = u.imag(), vr = v.real(), vi = v.imag();
    const Eigen::VectorXd re = real(ur, vr) - real(ui, vi);
    const Eigen::VectorXd im = real(ur, vi) + real(ui, vr);
    Eigen::VectorXcd out(re.size());
    for (Eigen::Index k = 0; k < re.size(); ++k) out[k] = Complex(re[k], im[k]);
    return out;
  }

 private:
  std::vector<double> lift(const Eigen::VectorXd& u) const {
    const std::vector<double>& x = grid_.sizes();
    std::vector<double> U(n_.size(), 0.0);
    double mass = 0.0;
    for (std::size_t k = 0; k < m_; ++k) {
      U[k] = u[Eigen::Index(k)];
      mass += x[k] * U[k];
    }
    U[m_] = -mass / x[m_];
    return U;
  }

  Eigen::VectorXd real(const Eigen::VectorXd& u, const Eigen::VectorXd& v) {
    Eigen::VectorXd out = Eigen::VectorXd::Zero(Eigen::Index(m_));
    const std::vector<double> U = lift(u), V = lift(v);
    double largest = 0.0;
    for (double w : U) largest = std::max(largest, std::abs(w));
    if (largest == 0.0 || V == std::vector<double>(V.size(), 0.0)) return out;
    const double s = top_ / largest;
    std::vector<double> moved(n_), at(n_.size()), base(n_.size());
    for (std::size_t k = 0; k < n_.size(); ++k) moved[k] += s * U[k];
    rates_->jacobian_times(0.0, moved, V, at);
    rates_->jacobian_times(0.0, n_, V, base);
    for (std::size_t k = 0; k < m_; ++k) out[Eigen::Index(k)] = (at[k] - base[k]) / s;
    return out;
  }

  const Discretisation& grid_;
  std::unique_ptr<Rates> rates_;
  std::vector<double> n_;
  std::size_t m_;
  double top_ = 0.0;
};

void check_state(const AggregationModel& model, std::span<const double> steady) {
  if (steady.size() != model.unknowns())
    throw InputError("steady_state", std::to_string(steady.size()) + " entries",
                     "exactly one per size class (" + std::to_string(model.unknowns()) + ")");
  for (double v : steady)
    if (!std::isfinite(v)) throw InputError("steady_state", format_value(v), "finite densities");
}

}  // namespace

double shifted_density(double n, double shift) {
  if (shift >= 0.0 || n <= 0.0) return std::max(0.0, n + shift);
  return n * std::exp(shift / n);
}

double HopfNormalForm::radius() const {
  const double r2 = -mu.real() / c1.real();
  return r2 >= 0.0 ? std::sqrt(r2) : nan;
}

double HopfNormalForm::frequency() const {
  const double r = radius();
  return mu.imag() + c1.imag() * r * r;
}

double HopfNormalForm::m0_half_range() const {
  Complex sum = 0.0;
  for (const Complex& v : q) sum += v;
  return 2.0 * radius() * std::abs(sum);
}

std::vector<double> HopfNormalForm::cycle_point(std::span<const double> steady) const {
  const double r = radius();
  if (!std::isfinite(r) || r == 0.0)
    throw std::runtime_error("the normal form predicts no cycle here (Re mu = " + format_value(mu.real()) +
                             ", Re c1 = " + format_value(c1.real()) + ")");
  std::vector<double> point(steady.begin(), steady.end());
  for (std::size_t k = 0; k < point.size() && k < q.size(); ++k) point[k] = shifted_density(point[k], 2.0 * r * q[k].real());
  return point;
}

HopfNormalForm hopf_normal_form(const AggregationModel& model, std::span<const double> steady) {
  check_state(model, steady);
  MassConstrainedSystem system(model);
  const std::size_t m = system.mass_row();
  const Discretisation& grid = system.discretisation();
  HopfNormalForm form;
  form.mu = rightmost_complex_pair(analyse_stability(model, steady, 6).rightmost);
  if (!std::isfinite(form.mu.real()))
    throw std::runtime_error("the spectrum has no complex pair: no Hopf normal form");
  const Eigen::MatrixXd A = mass_shell_jacobian(grid, steady, m);
  const Eigen::Index M = A.rows();
  const Eigen::MatrixXcd Ac = A.cast<Complex>();
  const Eigen::VectorXcd q = eigenvector(Ac, form.mu);
  Eigen::VectorXcd p = eigenvector(Ac.transpose(), std::conj(form.mu));
  p /= std::conj(p.dot(q));  // Eigen's dot conjugates the first argument: p̄ᵀ q = 1
  const double scale = A.cwiseAbs().rowwise().sum().maxCoeff();
  form.eigen_residual = std::max((Ac * q - form.mu * q).norm() / q.norm(),
                                 (Ac.transpose() * p - std::conj(form.mu) * p).norm() / p.norm()) / scale;

  SecondDerivative B(grid, steady, m);
  const double omega = form.mu.imag();
  const Eigen::VectorXcd h11 = A.partialPivLu().solve(Eigen::VectorXd(B(q, q.conjugate()).real())).cast<Complex>();
  const Eigen::VectorXcd h20 =
      (Complex(0.0, 2.0 * omega) * Eigen::MatrixXcd::Identity(M, M) - Ac).partialPivLu().solve(B(q, q));
  form.c1 = 0.5 * p.dot(B(q.conjugate(), h20)) - p.dot(B(q, h11));
  form.lyapunov = form.c1.real() / omega;

  const std::vector<double>& x = grid.sizes();
  form.q.assign(steady.size(), Complex(0.0));
  Complex mass = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    form.q[k] = q[Eigen::Index(k)];
    mass += x[k] * form.q[k];
  }
  form.q[m] = -mass / x[m];
  return form;
}

}  // namespace aggkit

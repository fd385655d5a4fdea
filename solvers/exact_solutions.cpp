#include "solvers/exact_solutions.hpp"

#include <cmath>
#include <stdexcept>

namespace aggkit {

namespace {

// log n_k(t) for the three solvable kernels (monodisperse unit start); -inf where n_k = 0.
double log_density(const std::string& kernel, std::size_t k, double t) {
  const double kk = double(k);
  if (t == 0.0) return k == 1 ? 0.0 : -INFINITY;
  if (kernel == "constant") return std::log(4.0) - 2.0 * std::log(t + 2.0) + (kk - 1.0) * std::log(t / (t + 2.0));
  if (kernel == "sum") {
    const double tau = -std::expm1(-t);  // τ = 1 - e^{-t}
    return -t + (kk - 1.0) * std::log(kk * tau) - kk * tau - std::lgamma(kk + 1.0);
  }
  if (kernel == "product") {
    if (t >= 1.0) throw std::domain_error("product kernel: the exact solution used here holds only before gelation, t < 1");
    return (kk - 1.0) * std::log(kk * t) - kk * t - std::log(kk) - std::lgamma(kk + 1.0);
  }
  throw std::invalid_argument("no exact solution for kernel '" + kernel + "'");
}

}  // namespace

bool has_exact_solution(const std::string& kernel_name) {
  return kernel_name == "constant" || kernel_name == "sum" || kernel_name == "product";
}

double exact_density(const std::string& kernel_name, std::size_t k, double t) {
  return std::exp(log_density(kernel_name, k, t));
}

std::vector<double> exact_distribution(const std::string& kernel_name, std::size_t N, double t) {
  std::vector<double> n(N);
  for (std::size_t k = 1; k <= N; ++k) n[k - 1] = exact_density(kernel_name, k, t);
  return n;
}

double exact_moment(const std::string& kernel_name, double p, double t) {
  if (kernel_name == "product" && t >= 1.0)
    throw std::domain_error("product kernel: moments are finite only before gelation, t < 1");
  if (p == 0.0 || p == 1.0 || p == 2.0) {
    const int q = int(p);
    if (kernel_name == "constant") return q == 0 ? 2.0 / (t + 2.0) : q == 1 ? 1.0 : 1.0 + t;
    if (kernel_name == "sum") return q == 0 ? std::exp(-t) : q == 1 ? 1.0 : std::exp(2.0 * t);
    if (kernel_name == "product") return q == 0 ? 1.0 - 0.5 * t : q == 1 ? 1.0 : 1.0 / (1.0 - t);
  }
  // Series: the terms rise to a maximum, then decay geometrically (constant, sum) or like
  // k^{p-5/2} e^{-k c(t)} (sum, product); stop once they have fallen below 1e-17 of the sum past the peak.
  double sum = 0.0, previous = 0.0;
  for (std::size_t k = 1; k < 100'000'000; ++k) {
    const double term = std::exp(p * std::log(double(k)) + log_density(kernel_name, k, t));
    sum += term;
    if (k > 8 && term < previous && term < 1e-17 * sum) return sum;
    previous = term;
    if (t == 0.0) return sum;
  }
  throw std::runtime_error("exact_moment: series did not converge");
}

double exact_total_density_k2(double lambda, double t) {
  if (lambda == 0.0) return 1.0 / (1.0 + t);
  const double steady = 2.0 * lambda / (1.0 + 2.0 * lambda);
  return steady / (1.0 + (steady - 1.0) * std::exp(-2.0 * lambda * t));
}

std::vector<double> exact_total_density_k2(double lambda, const std::vector<double>& times) {
  std::vector<double> m0;
  for (double t : times) m0.push_back(exact_total_density_k2(lambda, t));
  return m0;
}

}  // namespace aggkit

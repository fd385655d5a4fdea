#include "analysis/moments.hpp"

#include <cmath>

namespace aggkit {

namespace {
// Neumaier's variant [Neumaier1974] of Kahan summation [Kahan1965].
struct CompensatedSum {
  double sum = 0.0, compensation = 0.0;
  void add(double x) {
    const double t = sum + x;
    compensation += std::abs(sum) >= std::abs(x) ? (sum - t) + x : (x - t) + sum;
    sum = t;
  }
  double value() const { return sum + compensation; }
};

double size_power(std::size_t k, double p) {
  if (p == 0.0) return 1.0;
  if (p == 1.0) return double(k);
  if (p == 2.0) return double(k) * double(k);
  if (p == 3.0) return double(k) * double(k) * double(k);
  return std::pow(double(k), p);
}
}  // namespace

double moment(std::span<const double> n, double p) {
  CompensatedSum s;
  for (std::size_t k = 1; k <= n.size(); ++k) s.add(size_power(k, p) * n[k - 1]);
  return s.value();
}

std::vector<double> moments(std::span<const double> n, std::span<const double> orders) {
  std::vector<CompensatedSum> sums(orders.size());
  for (std::size_t k = 1; k <= n.size(); ++k)
    for (std::size_t q = 0; q < orders.size(); ++q) sums[q].add(size_power(k, orders[q]) * n[k - 1]);
  std::vector<double> out(orders.size());
  for (std::size_t q = 0; q < orders.size(); ++q) out[q] = sums[q].value();
  return out;
}

double relative_error(double value, double reference) {
  const double diff = std::abs(value - reference);
  return reference != 0.0 ? diff / std::abs(reference) : diff;
}

}  // namespace aggkit

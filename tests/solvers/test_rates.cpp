// The fast O(N R log N) right-hand side, its Jacobian-vector product, diagonal and leak rate agree with
// the direct O(N^2) oracle (written term by term from the equations) for every kernel, both truncations,
// λ = 0 and λ > 0; and the right-hand side conserves mass to round-off.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "solvers/rates.hpp"

using namespace aggkit;

namespace {

AggregationModel test_model(const Kernel& kernel, double lambda, Truncation truncation, std::size_t N) {
  AggregationModel m;
  m.kernel = kernel;
  m.lambda = ShatteringRate::constant(lambda);
  m.size = N;
  m.truncation = truncation;
  m.initial = monodisperse(N);
  return m;
}

// A smooth, slowly decaying positive state (every size matters) and a signed direction vector.
std::vector<double> state(std::size_t N) {
  std::vector<double> n(N);
  for (std::size_t k = 1; k <= N; ++k) n[k - 1] = std::exp(-double(k) / 40.0) / double(k);
  return n;
}
std::vector<double> direction(std::size_t N) {
  std::vector<double> v(N);
  for (std::size_t k = 1; k <= N; ++k) v[k - 1] = std::sin(0.37 * double(k)) * std::exp(-double(k) / 60.0);
  return v;
}

// max_k |a_k - b_k| / (|b_k| + 1e-4 max|b|). An FFT convolution errs by about ε log2(L) max|b| in
// every entry whatever its size, so where gain and loss cancel (f_k ≈ 0) only that absolute error is
// meaningful: a bound of 1e-10 on this measure allows 1e-10 relative error plus 1e-14 max|b| (≈ 50 ε).
double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double largest = 0.0;
  for (double x : b) largest = std::max(largest, std::abs(x));
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
    worst = std::max(worst, std::abs(a[k] - b[k]) / (std::abs(b[k]) + 1e-4 * largest));
  return worst;
}

}  // namespace

TEST_CASE("fast rates equal the direct oracle for every kernel", "[rates]") {
  const std::size_t N = 300;
  const auto n = state(N), v = direction(N);
  for (const Kernel& kernel : {Kernel::constant(), Kernel::sum(), Kernel::product(), Kernel::linear(0.5, 0.25),
                               Kernel::generalized_product(0.5), Kernel::ballistic(), Kernel::brownian(0.95),
                               Kernel::brownian(0.0)}) {
    for (double lambda : {0.0, 0.3}) {
      for (Truncation truncation : {Truncation::drop, Truncation::cutoff}) {
        const AggregationModel model = test_model(kernel, lambda, truncation, N);
        INFO(kernel.describe() << " lambda=" << lambda << " " << to_string(truncation));
        auto fast = make_fast_rates(model, 1e-13);
        auto direct = make_direct_rates(model);
        std::vector<double> f1(N), f2(N), j1(N), j2(N);
        Rates::MonomerCoupling c1, c2;
        fast->evaluate(0.0, n, f1);
        direct->evaluate(0.0, n, f2);
        fast->jacobian_times(0.0, n, v, j1);
        direct->jacobian_times(0.0, n, v, j2);
        fast->jacobian_monomer_coupling(0.0, n, c1);
        direct->jacobian_monomer_coupling(0.0, n, c2);
        // FFT round-off (~1e-16 · log N relative to the largest entries) and, for ballistic, the
        // 1e-13 kernel approximation: 1e-10 leaves a wide margin while catching any wrong term.
        CHECK(relative_difference(f1, f2) < 1e-10);
        CHECK(relative_difference(j1, j2) < 1e-10);
        CHECK(relative_difference(c1.diagonal, c2.diagonal) < 1e-10);
        CHECK(relative_difference(c1.subdiagonal, c2.subdiagonal) < 1e-10);
        CHECK(relative_difference(c1.monomer_column, c2.monomer_column) < 1e-10);
        CHECK(fast->leak_rate(0.0, n) == Approx(direct->leak_rate(0.0, n)).epsilon(1e-11).margin(1e-300));
      }
    }
  }
}

TEST_CASE("the right-hand side conserves mass up to the leak", "[rates][conservation]") {
  const std::size_t N = 500;
  const auto n = state(N);
  for (Truncation truncation : {Truncation::drop, Truncation::cutoff}) {
    for (RatesPath path : {RatesPath::fast, RatesPath::direct}) {
      const AggregationModel model = test_model(Kernel::ballistic(), 0.7, truncation, N);
      auto rates = make_rates(model, path, 1e-12);
      std::vector<double> f(N);
      rates->evaluate(0.0, n, f);
      double mass_rate = 0.0, scale = 0.0;
      for (std::size_t k = 1; k <= N; ++k) mass_rate += double(k) * f[k - 1], scale += double(k) * std::abs(f[k - 1]);
      const double leak = rates->leak_rate(0.0, n);
      INFO(to_string(truncation) << " " << to_string(path));
      CHECK(std::abs(mass_rate + leak) < 1e-13 * scale);
      if (truncation == Truncation::cutoff) CHECK(leak == 0.0);
      if (truncation == Truncation::drop) CHECK(leak > 0.0);
    }
  }
}

TEST_CASE("the Jacobian-vector product is the derivative of the right-hand side", "[rates]") {
  // f is quadratic in n, so f(n + h v) - f(n - h v) = 2 h J v exactly (up to round-off).
  const std::size_t N = 256;
  const auto n = state(N), v = direction(N);
  const AggregationModel model = test_model(Kernel::brownian(0.7), 0.2, Truncation::drop, N);
  auto rates = make_fast_rates(model);
  std::vector<double> plus(N), minus(N), fp(N), fm(N), jv(N), difference(N);
  const double h = 1e-3;
  for (std::size_t k = 0; k < N; ++k) plus[k] = n[k] + h * v[k], minus[k] = n[k] - h * v[k];
  rates->evaluate(0.0, plus, fp);
  rates->evaluate(0.0, minus, fm);
  rates->jacobian_times(0.0, n, v, jv);
  for (std::size_t k = 0; k < N; ++k) difference[k] = (fp[k] - fm[k]) / (2 * h);
  CHECK(relative_difference(difference, jv) < 1e-9);
}

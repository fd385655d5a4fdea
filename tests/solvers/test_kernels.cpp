// Kernels: values, exact separable forms reproduce K_ij, the low-rank ballistic approximation meets its
// tolerance (measured on every entry here, independently of the error the approximation reports).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

#include "analysis/input_error.hpp"
#include "solvers/kernels.hpp"
#include "solvers/low_rank.hpp"

using namespace aggkit;

namespace {
double max_relative_error_all_entries(const Kernel& kernel, const SeparableForm& form, std::size_t N) {
  double worst = 0.0;
  for (std::size_t i = 1; i <= N; ++i)
    for (std::size_t j = 1; j <= N; ++j) {
      const double exact = kernel(i, j);
      worst = std::max(worst, std::abs(separable_entry(form, i, j) - exact) / exact);
    }
  return worst;
}
}  // namespace

TEST_CASE("kernel values follow their formulas", "[kernels]") {
  CHECK(Kernel::constant()(3, 7) == 1.0);
  CHECK(Kernel::sum()(3, 7) == 10.0);
  CHECK(Kernel::product()(3, 7) == 21.0);
  CHECK(Kernel::linear(0.5, 2.0)(3, 7) == Approx(1.0 + 0.5 * 10 + 2.0 * 21));
  CHECK(Kernel::generalized_product(0.5)(4, 9) == Approx(6.0));
  CHECK(Kernel::brownian(0.0)(5, 11) == 2.0);
  CHECK(Kernel::brownian(1.0)(2, 4) == Approx(2.5));
  // Ballistic K_11 = (1+1)^2 sqrt(2) and K_{8,1} = (2+1)^2 sqrt(1 + 1/8).
  CHECK(Kernel::ballistic()(1, 1) == Approx(4.0 * std::sqrt(2.0)));
  CHECK(Kernel::ballistic()(8, 1) == Approx(9.0 * std::sqrt(1.125)));
}

TEST_CASE("exact separable forms reproduce every kernel entry", "[kernels]") {
  const std::size_t N = 300;
  for (const Kernel& kernel : {Kernel::constant(), Kernel::sum(), Kernel::product(), Kernel::linear(0.3, 0.7),
                               Kernel::generalized_product(0.4), Kernel::brownian(0.95), Kernel::brownian(0.0)}) {
    INFO(kernel.describe());
    const SeparableForm form = kernel.separable_form(N);
    CHECK(form.exact);
    CHECK(form.rank() <= 2);
    // Round-off only: the features are sums of at most 4 products of O(N^2) numbers.
    CHECK(max_relative_error_all_entries(kernel, form, N) < 1e-13);
  }
}

TEST_CASE("ballistic low-rank approximation meets the requested tolerance", "[kernels][lowrank]") {
  const Kernel kernel = Kernel::ballistic();
  const std::size_t N = 1500;
  std::size_t previous_rank = 0;
  for (double tol : {1e-4, 1e-8, 1e-11}) {
    const SeparableForm form = kernel.separable_form(N, tol);
    INFO("tolerance " << tol << " rank " << form.rank());
    CHECK_FALSE(form.exact);
    const double measured = max_relative_error_all_entries(kernel, form, N);
    CHECK(measured <= tol);
    // Beyond N = 256 the reported error is measured on 65 sampled rows: never above the error on all entries.
    CHECK(form.max_relative_error <= measured + 1e-15);
    CHECK(form.rank() >= previous_rank);  // tighter tolerance never needs fewer terms
    CHECK(form.rank() < 80);              // and stays low rank
    previous_rank = form.rank();
  }
}

TEST_CASE("up to N = 256 the reported low-rank error is the error on all entries", "[kernels][lowrank]") {
  const Kernel kernel = Kernel::ballistic();
  for (std::size_t N : {100, 256}) {
    const SeparableForm form = kernel.separable_form(N, 1e-8);
    INFO("N " << N << " rank " << form.rank());
    CHECK(form.max_relative_error == Approx(max_relative_error_all_entries(kernel, form, N)).margin(1e-15));
    CHECK(form.checked_entries >= N * N);
  }
}

TEST_CASE("low-rank approximation never forms the matrix and still holds at large N", "[kernels][lowrank]") {
  const Kernel kernel = Kernel::ballistic();
  const std::size_t N = 1 << 15;
  const SeparableForm form = kernel.separable_form(N, 1e-10);
  INFO("rank " << form.rank() << " reported error " << form.max_relative_error);
  CHECK(form.max_relative_error <= 1e-10);
  CHECK(form.checked_entries > 50 * N);  // 50 full rows (and by symmetry columns) and a diagonal sample
  // An independent check against direct evaluation on entries the reported error need not have covered:
  // the corners (small i with large j), sizes between the factorisation's skeleton points, random entries.
  for (std::size_t i : {1, 2, 3, 17, 70, 777, 4321, 20000, 32766, 32767, 32768})
    for (std::size_t j : {1, 3, 99, 1000, 16385, 30001, 32767, 32768})
      CHECK(std::abs(separable_entry(form, i, j) / kernel(i, j) - 1.0) <= 1e-10);
  std::mt19937_64 random(7);
  double worst = 0.0;
  for (int e = 0; e < 20000; ++e) {
    const std::size_t i = 1 + random() % N, j = 1 + random() % N;
    worst = std::max(worst, std::abs(separable_entry(form, i, j) / kernel(i, j) - 1.0));
  }
  CHECK(worst <= 1e-10);
}

TEST_CASE("low-rank factors meet the steady state's tolerance 1e-12 at large N", "[kernels][lowrank]") {
  // The steady-state solver asks for 1e-12 (solvers/steady_state.hpp); the ratio max K / min K ≈ 300 at
  // N = 2^15 leaves round-off two and a half digits of room at double precision.
  const Kernel kernel = Kernel::ballistic();
  const std::size_t N = 1 << 15;
  const SeparableForm form = kernel.separable_form(N, 1e-12);
  INFO("rank " << form.rank() << " reported error " << form.max_relative_error);
  CHECK(form.max_relative_error <= 1e-12);
  CHECK(form.rank() < 60);
  std::mt19937_64 random(11);
  double worst = 0.0;
  for (int e = 0; e < 20000; ++e) {
    const std::size_t i = 1 + random() % 64, j = 1 + random() % N;  // the corner: small i, any j
    const std::size_t k = 1 + random() % N, l = 1 + random() % N;
    worst = std::max({worst, std::abs(separable_entry(form, i, j) / kernel(i, j) - 1.0),
                      std::abs(separable_entry(form, k, l) / kernel(k, l) - 1.0)});
  }
  CHECK(worst <= 1e-12);
}

TEST_CASE("cross approximation recovers an exactly rank-2 indefinite kernel", "[kernels][lowrank]") {
  // (i/j)^a + (j/i)^a = x_i y_j + y_i x_j with x = s^a, y = s^-a: rank 2 with eigenvalues of both signs,
  // so the symmetric elimination needs a 2×2 pivot; every entry must come back to round-off.
  const Kernel brownian = Kernel::brownian(0.5);
  const std::size_t N = 1000;
  const SeparableForm form =
      cross_approximation([&](std::size_t i, std::size_t j) { return brownian(i, j); }, N, 1e-12);
  CHECK(form.rank() == 2);
  CHECK(max_relative_error_all_entries(brownian, form, N) <= 1e-13);
}

TEST_CASE("bad kernel input names the key", "[kernels][input]") {
  CHECK_THROWS_WITH(Kernel::from_name("gravity", {}), Catch::Contains("kernel.name") && Catch::Contains("gravity"));
  CHECK_THROWS_WITH(Kernel::from_name("brownian", {{"a", -0.1}}), Catch::Contains("kernel.a"));
  CHECK_THROWS_WITH(Kernel::from_name("brownian", {{"a", 1.5}}), Catch::Contains("[0, 1]"));
  CHECK_THROWS_WITH(Kernel::from_name("brownian", {{"a", NAN}}), Catch::Contains("nan"));
  CHECK_THROWS_WITH(Kernel::from_name("brownian", {}), Catch::Contains("kernel.a"));
  CHECK_THROWS_WITH(Kernel::from_name("constant", {{"a", 1.0}}), Catch::Contains("kernel.a"));
  CHECK_THROWS_AS(Kernel::from_name("linear", {{"A", -1.0}}), InputError);
  CHECK(Kernel::from_name("brownian", {{"a", 0.0}})(2, 3) == 2.0);  // a = 0 is valid: K = 2
}

TEST_CASE("ballistic2d: the kinetic-theory rate of Maxwellian discs, by Monte Carlo and in its limits", "[kernels]") {
  const Kernel kernel = Kernel::ballistic2d();
  CHECK(Kernel::from_name("ballistic2d", {})(3, 5) == kernel(3, 5));
  // Limits: K_11 = 2√2; degree 0 (K_{si,sj} = K_ij: the 2-D compact kernel is scale invariant, so the
  // cluster density decays as 1/t [Carnevale1990]); a monomer against a large cluster, K_1j → sqrt(j).
  CHECK(kernel(1, 1) == Approx(2.0 * std::sqrt(2.0)));
  CHECK(kernel(7, 300) == Approx(kernel(70, 3000)).epsilon(1e-12));
  CHECK(kernel(1, 1000000) / std::sqrt(1e6) == Approx(1.0).epsilon(2e-3));  // (1 + 1/√j) sqrt(1 + 1/j)

  // The physical rate 2(R_i + R_j) <|v_i - v_j|> of discs of radius R√k and mass m k with 2-D Maxwellian
  // velocities at temperature T, averaged over 10^6 sampled pairs, equals K0 K_ij with K0 = R sqrt(2πT/m).
  // The sampled mean speed has relative sd sqrt((4 - π)/π)/sqrt(10^6) = 5e-4: 3e-3 is 6 sd.
  const double R = 0.5, T = 0.7, m = 1.3, K0 = R * std::sqrt(2 * std::acos(-1.0) * T / m);
  std::mt19937_64 random(42);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (const auto& [i, j] : {std::pair{1, 1}, std::pair{1, 2}, std::pair{3, 40}, std::pair{100, 100}}) {
    const double si = std::sqrt(T / (m * i)), sj = std::sqrt(T / (m * j));  // velocity sd per component
    double sum = 0;
    const int samples = 1000000;
    for (int s = 0; s < samples; ++s) {
      const double gx = si * gauss(random) - sj * gauss(random), gy = si * gauss(random) - sj * gauss(random);
      sum += std::hypot(gx, gy);
    }
    const double rate = 2 * R * (std::sqrt(double(i)) + std::sqrt(double(j))) * sum / samples;
    INFO("i = " << i << ", j = " << j);
    CHECK(rate == Approx(K0 * kernel(i, j)).epsilon(3e-3));
  }
  // K_11 n K0 is the collision frequency of a hard-disc gas, 2σ n sqrt(πT/m) with σ = 2R [BrilliantovPoschel2004].
  CHECK(K0 * kernel(1, 1) == Approx(2 * (2 * R) * std::sqrt(std::acos(-1.0) * T / m)));

  // No exact factorisation: the low-rank approximation meets its tolerance on every entry.
  const SeparableForm form = kernel.separable_form(400, 1e-10);
  CHECK_FALSE(form.exact);
  CHECK(max_relative_error_all_entries(kernel, form, 400) <= 1e-10);
}

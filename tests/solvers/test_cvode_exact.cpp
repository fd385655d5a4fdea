// CVODE integration against the exact solutions of pure aggregation (λ = 0), for each integrator.
// Tolerance budget: the truncation N is chosen so that the exact tail beyond N is below e^{-40}
// (negligible), so the error is the integration error; with rtol = 1e-10 the global relative error of
// the moments is observed at ~1e-9, and the checks allow 1e-7 (bdf/adams at rtol 1e-10).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "analysis/moments.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/exact_solutions.hpp"

using namespace aggkit;

namespace {

struct Worst {
  double moment = 0.0, density = 0.0;
};

Worst compare_with_exact(const Kernel& kernel, std::size_t N, const std::vector<double>& times,
                         IntegratorOptions options) {
  AggregationModel model;
  model.kernel = kernel;
  model.size = N;
  model.initial = monodisperse(N);
  Worst worst;
  integrate(model, times, options, [&](double t, std::span<const double> n, double) {
    for (double p : {0.0, 1.0, 2.0, 3.0}) {
      const double error = relative_error(moment(n, p), exact_moment(kernel.name(), p, t));
      INFO(kernel.name() << " t=" << t << " M" << p << " error " << error);
      worst.moment = std::max(worst.moment, error);
    }
    for (std::size_t k : {1, 2, 5, 10, 30})  // densities that are not negligibly small
      if (exact_density(kernel.name(), k, t) > 1e-8)
        worst.density = std::max(worst.density, relative_error(n[k - 1], exact_density(kernel.name(), k, t)));
  });
  return worst;
}

}  // namespace

TEST_CASE("exact moments: closed forms agree with the series", "[exact]") {
  CHECK(exact_moment("constant", 3.0, 4.0) == Approx(1.0 + 3 * 4.0 + 1.5 * 16.0).epsilon(1e-13));
  for (const char* kernel : {"constant", "sum", "product"})
    for (double t : {0.1, 0.5, 0.9}) {
      double series0 = 0, series2 = 0;
      for (std::size_t k = 1; k < 200000; ++k) {
        const double n = exact_density(kernel, k, t);
        series0 += n, series2 += double(k) * double(k) * n;
      }
      CHECK(series0 == Approx(exact_moment(kernel, 0.0, t)).epsilon(1e-12));
      CHECK(series2 == Approx(exact_moment(kernel, 2.0, t)).epsilon(1e-10));
    }
}

TEST_CASE("constant kernel matches n_k = 4/(t+2)^2 (t/(t+2))^{k-1}", "[cvode][exact]") {
  IntegratorOptions options;
  options.rtol = 1e-10;
  // (t/(t+2))^{N-1} < e^{-40} at t = 100 needs N ≈ 2100.
  const Worst w = compare_with_exact(Kernel::constant(), 4096, {1.0, 10.0, 100.0}, options);
  CHECK(w.moment < 1e-7);
  CHECK(w.density < 1e-7);
}

TEST_CASE("sum kernel matches M0 = e^{-t}, M2 = e^{2t}", "[cvode][exact]") {
  IntegratorOptions options;
  options.rtol = 1e-10;
  // At t = 2 the tail decays like e^{-0.0101 k}: N = 4096 leaves e^{-41}.
  const Worst w = compare_with_exact(Kernel::sum(), 4096, {0.5, 1.0, 2.0}, options);
  CHECK(w.moment < 1e-7);
  CHECK(w.density < 1e-7);
}

TEST_CASE("product kernel matches M2 = 1/(1-t) before gelation", "[cvode][exact]") {
  IntegratorOptions options;
  options.rtol = 1e-10;
  // At t = 0.8 the tail decays like k^{-5/2} e^{-0.0231 k}: N = 2048 leaves e^{-47}.
  const Worst w = compare_with_exact(Kernel::product(), 2048, {0.2, 0.5, 0.8}, options);
  CHECK(w.moment < 1e-7);
  CHECK(w.density < 1e-7);
}

TEST_CASE("every integrator reproduces the constant-kernel solution", "[cvode][exact]") {
  for (IntegratorMethod method : {IntegratorMethod::bdf_gmres, IntegratorMethod::bdf_dense, IntegratorMethod::adams,
                                  IntegratorMethod::erk, IntegratorMethod::automatic}) {
    for (RatesPath path : {RatesPath::fast, RatesPath::direct}) {
      IntegratorOptions options;
      options.method = method;
      options.rates = path;
      options.rtol = 1e-10;
      INFO(to_string(method) << " " << to_string(path));
      // (10/12)^{N-1} < e^{-40} for N = 250.
      const Worst w = compare_with_exact(Kernel::constant(), 300, {1.0, 10.0}, options);
      CHECK(w.moment < 1e-7);
      CHECK(w.density < 1e-7);
    }
  }
}

TEST_CASE("every preconditioner gives the same solution", "[cvode]") {
  AggregationModel model;
  model.kernel = Kernel::ballistic();
  model.lambda = ShatteringRate::constant(0.05);
  model.size = 1000;
  model.initial = monodisperse(model.size);
  std::vector<double> reference;
  for (Preconditioner p : {Preconditioner::monomer, Preconditioner::jacobi, Preconditioner::none}) {
    IntegratorOptions options;
    options.rtol = 1e-9;
    options.atol = 1e-11;
    options.atol_exponent = 3.0;
    options.preconditioner = p;
    std::vector<double> result;
    integrate(model, std::vector<double>{1.0, 30.0}, options, [&](double, std::span<const double> n, double) {
      for (double q : {0.0, 2.0, 3.0}) result.push_back(moment(n, q));
    });
    if (reference.empty()) reference = result;
    for (std::size_t i = 0; i < result.size(); ++i) CHECK(result[i] == Approx(reference[i]).epsilon(1e-7));
  }
}

TEST_CASE("max_steps stops a run with a clear error", "[cvode][input]") {
  AggregationModel model;
  model.kernel = Kernel::constant();
  model.size = 100;
  model.initial = monodisperse(model.size);
  IntegratorOptions options;
  options.max_steps = 5;
  for (IntegratorMethod method : {IntegratorMethod::bdf_gmres, IntegratorMethod::erk, IntegratorMethod::automatic}) {
    options.method = method;
    CHECK_THROWS_WITH(integrate(model, std::vector<double>{10.0}, options, [](double, std::span<const double>, double) {}),
                      Catch::Contains("max_steps = 5"));
  }
  options.rtol = -1.0;
  CHECK_THROWS_WITH(integrate(model, std::vector<double>{10.0}, options, [](double, std::span<const double>, double) {}),
                    Catch::Contains("rtol = -1"));
}

TEST_CASE("on_step sees every internal step's densities, which follow the exact solution", "[cvode][exact]") {
  // The constant kernel, M0 = 2/(t+2): each method's steps are reported once each, in time order, with the
  // densities the step accepted (no interpolant), whose M0 the tolerance bounds like the outputs'.
  AggregationModel model;
  model.kernel = Kernel::constant();
  model.size = 300;
  model.initial = monodisperse(model.size);
  for (IntegratorMethod method : {IntegratorMethod::bdf_gmres, IntegratorMethod::erk, IntegratorMethod::automatic}) {
    INFO(to_string(method));
    IntegratorOptions options;
    options.method = method;
    options.rtol = 1e-10;
    std::vector<double> times;
    double worst = 0.0;
    options.on_step = [&](double t, std::span<const double> n) {
      REQUIRE(n.size() == model.size);
      times.push_back(t);
      worst = std::max(worst, relative_error(moment(n, 0.0), exact_moment("constant", 0.0, t)));
    };
    const IntegratorStatistics stats = integrate(model, std::vector<double>{1.0, 10.0}, options, [](double, std::span<const double>, double) {});
    CHECK(long(times.size()) == stats.steps);
    CHECK(std::is_sorted(times.begin(), times.end()));
    CHECK(std::adjacent_find(times.begin(), times.end()) == times.end());
    REQUIRE(!times.empty());
    CHECK(times.back() >= 10.0);  // the last step reaches (or passes) the last output
    CHECK(worst < 1e-7);
  }
}

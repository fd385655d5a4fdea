// The adaptive active size range of the fast right-hand side (solvers/rates_fast.cpp): sizes beyond the
// last one with |n_k| > ν_k = negligible_fraction · atol_k take no part in collisions. The truncated
// system differs from the full one by terms of order ν_k (10^-6 of the absolute tolerance by default), so
// a run with the active range must agree with a full-range run (negligible_fraction = 0) to within the
// integration tolerance, and both with the exact solution where there is one; and the range must
// actually be shorter than N while the distribution is.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "analysis/moments.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/exact_solutions.hpp"

using namespace aggkit;

namespace {

struct Run {
  std::vector<std::vector<double>> n;  // densities at each output
  IntegratorStatistics statistics;
};

Run run(const AggregationModel& model, const std::vector<double>& times, IntegratorOptions options) {
  Run r;
  r.statistics = integrate(model, times, options, [&](double, std::span<const double> n, double) {
    r.n.emplace_back(n.begin(), n.end());
  });
  return r;
}

// Largest |n_k - m_k| / (rtol |m_k| + atol_k): below ~1 the two states agree within the error weights.
double weighted_difference(const std::vector<double>& n, const std::vector<double>& m, const IntegratorOptions& o,
                           double floor) {
  double worst = 0.0;
  for (std::size_t k = 1; k <= n.size(); ++k) {
    const double atol_k = std::max(o.effective_atol() * std::pow(double(k), -o.atol_exponent), floor);
    worst = std::max(worst, std::abs(n[k - 1] - m[k - 1]) / (o.rtol * std::abs(m[k - 1]) + atol_k));
  }
  return worst;
}

}  // namespace

// K = 2 (brownian a = 0), λ = 0, N = 8192, cutoff: M0 = 1/(1+t), M2 = 1+2t, M3 = 1+6t+6t² exactly (the
// tail beyond N at t = 100 is (100/101)^N = e^{-81}, tests/solvers/test_tolerance_proportionality.cpp).
// n_k = (1+t)^-2 (t/(1+t))^{k-1} falls below ν_k = 1e-6 max(1e-10/k³, 1e-18) (rtol 1e-8: atol 1e-10, floor
// 1e-18) near k = 70 at t = 1 and near k = 4600 at t = 100, so the range must grow from tens of sizes to
// thousands and stay below N.
TEST_CASE("active range: constant kernel with exact moments, adaptive = full range = exact", "[cvode][active-range]") {
  AggregationModel model;
  model.kernel = Kernel::brownian(0.0);
  model.size = 8192;
  model.truncation = Truncation::cutoff;
  model.initial = monodisperse(model.size);
  const std::vector<double> times{1.0, 10.0, 100.0};
  IntegratorOptions adaptive;
  adaptive.rtol = 1e-8;
  IntegratorOptions full = adaptive;
  full.negligible_fraction = 0.0;
  const Run a = run(model, times, adaptive), f = run(model, times, full);
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double t = times[i];
    for (const auto& [p, exact] : {std::pair{0.0, 1.0 / (1.0 + t)}, std::pair{2.0, 1.0 + 2.0 * t},
                                   std::pair{3.0, 1.0 + 6.0 * t + 6.0 * t * t}}) {
      INFO("t = " << t << " M" << p);
      // The tolerance target: every moment within 10 rtol of the exact value, with or without the range.
      CHECK(relative_error(moment(a.n[i], p), exact) <= 10.0 * adaptive.rtol);
      CHECK(relative_error(moment(f.n[i], p), exact) <= 10.0 * adaptive.rtol);
    }
    // Size by size the two runs agree within the error weights CVODE controls (each run's local errors are
    // below them; the global error adds up to a few weights).
    INFO("t = " << t);
    CHECK(weighted_difference(a.n[i], f.n[i], adaptive, a.statistics.atol_floor) <= 10.0);
  }
  // The range grows with the distribution and stays below N (the exact tail crosses ν_k near k = 4600).
  CHECK(a.statistics.active_size_final > 1000);
  CHECK(a.statistics.active_size_final < model.size);
  CHECK(a.statistics.active_size_mean < 0.5 * double(model.size));
  CHECK(a.statistics.fft_work_fraction < 0.5);
  // Without levels only sizes below 1e-300 are left out (the tail underflows near k = 630 at t = 1, but
  // reaches N by t ≈ 40): the levels must save more than that.
  INFO("FFT work fraction: adaptive " << a.statistics.fft_work_fraction << ", full " << f.statistics.fft_work_fraction);
  CHECK(a.statistics.fft_work_fraction < 0.8 * f.statistics.fft_work_fraction);
  // A run stopped at t = 1 has a range of tens of sizes (the exact n_k crosses ν_k near k = 70).
  const Run early = run(model, {1.0}, adaptive);
  CHECK(early.statistics.active_size_final >= 55);
  CHECK(early.statistics.active_size_final <= 90);
}

// The README example (ballistic kernel, λ = 0.01, N = 5000, drop; validation/scenes/ballistic-shattering.toml)
// at its default tolerances: no exact solution, so the adaptive run is compared with the full-range run.
// Each has moment errors ~1e-7 against a tight reference (bench/results/log/cvode-work-precision.md, case b); their
// difference was measured at 2.7e-9, and the check allows the tolerance, 10 rtol.
TEST_CASE("active range: README example agrees with the full range", "[cvode][active-range]") {
  AggregationModel model;
  model.kernel = Kernel::ballistic();
  model.lambda = ShatteringRate::constant(0.01);
  model.size = 5000;
  model.truncation = Truncation::drop;
  model.initial = monodisperse(model.size);
  const std::vector<double> times{1.0, 10.0, 100.0};
  IntegratorOptions adaptive;  // rtol 1e-6, atol 1e-8/k³
  IntegratorOptions full = adaptive;
  full.negligible_fraction = 0.0;
  const Run a = run(model, times, adaptive), f = run(model, times, full);
  for (std::size_t i = 0; i < times.size(); ++i) {
    for (double p : {0.0, 2.0, 3.0}) {
      INFO("t = " << times[i] << " M" << p);
      CHECK(relative_error(moment(a.n[i], p), moment(f.n[i], p)) <= 10.0 * adaptive.rtol);
    }
    INFO("t = " << times[i]);
    CHECK(weighted_difference(a.n[i], f.n[i], adaptive, a.statistics.atol_floor) <= 10.0);
  }
  CHECK(a.statistics.active_size_final == model.size);  // at t = 100 the distribution reaches N
  CHECK(a.statistics.fft_work_fraction < 0.7);           // measured 0.53: the early times are cheap
}

// The explicit Runge–Kutta method (ARKODE) and `auto`, which hands a run over from it to BDF once the explicit
// step is bounded by stability [Petzold1983].
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "analysis/moments.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/erk_stepper.hpp"

using namespace aggkit;

TEST_CASE("the real stability boundary of Dormand-Prince 5(4) is the published 3.31", "[erk]") {
  // [DormandPrince1980]'s pair is stable on [-3.3066, 0] of the real axis (Hairer & Wanner, Solving ODEs II,
  // Sec. IV.2, the stability domain of DOPRI5); the search steps by 0.01.
  CHECK(integration::real_stability_boundary(ErkTable::dormand_prince_5) == Approx(3.30).margin(0.011));
  // Higher order with more stages reaches further along the axis, but less per stage.
  const double verner = integration::real_stability_boundary(ErkTable::verner_6);
  const double fehlberg = integration::real_stability_boundary(ErkTable::fehlberg_8);
  CHECK(verner > 3.31);
  CHECK(fehlberg > verner);
  CHECK(fehlberg / 13.0 < verner / 8.0);
}

namespace {

struct Run {
  std::vector<double> moments;  // M0, M2, M3 at each output
  IntegratorStatistics stats;
};

Run run(const AggregationModel& model, IntegratorMethod method, double rtol, double lowrank_tolerance = 0.0) {
  IntegratorOptions options;
  options.method = method;
  options.rtol = rtol;
  options.lowrank_tolerance = lowrank_tolerance;
  Run r;
  r.stats = integrate(model, std::vector<double>{1.0, 10.0, 100.0}, options, [&](double, std::span<const double> n, double) {
    for (double p : {0.0, 2.0, 3.0}) r.moments.push_back(moment(n, p));
  });
  return r;
}

AggregationModel ballistic(double lambda = 0.01, std::size_t size = 1000) {
  AggregationModel model;
  model.kernel = Kernel::ballistic();
  model.lambda = ShatteringRate::constant(lambda);
  model.size = size;
  model.truncation = Truncation::cutoff;
  model.initial = monodisperse(model.size);
  return model;
}

}  // namespace

// The ballistic kernel with shattering relaxes to a steady state whose largest loss rates (~20 at N = 2000)
// bound Dormand-Prince's step to h ≤ 3.3/ρ: at rtol 1e-6 past t ≈ 20 the explicit steps are set by stability
// (their number no longer falls with rtol), and BDF takes over. Checked against BDF at rtol 1e-10: the moments
// within 10 rtol (the bound of the tolerance tests).
TEST_CASE("auto hands the stiff ballistic run over to BDF and meets its tolerance", "[cvode][erk]") {
  const AggregationModel model = ballistic();
  const Run reference = run(model, IntegratorMethod::bdf_gmres, 1e-10);
  const Run automatic = run(model, IntegratorMethod::automatic, 1e-6);
  INFO("BDF from t = " << automatic.stats.stiff_from);
  CHECK(automatic.stats.stiff_from > 1.0);
  CHECK(automatic.stats.stiff_from < 100.0);
  CHECK(automatic.stats.linear_iterations > 0);  // BDF's Newton iterations ran after the switch
  for (std::size_t i = 0; i < reference.moments.size(); ++i)
    CHECK(relative_error(automatic.moments[i], reference.moments[i]) <= 1e-5);
}

// K = 2 without shattering: ρ = 2 M0 = 2/(1+t) only falls, so the explicit steps stay set by accuracy and
// auto never leaves them; its moments are the closed forms M0 = 1/(1+t), M2 = 1+2t, M3 = 1+6t+6t²
// [Leyvraz2003] within 10 rtol.
TEST_CASE("auto stays explicit where the run is not stiff", "[cvode][erk]") {
  AggregationModel model;
  model.kernel = Kernel::brownian(0.0);  // K_ij = 2
  model.size = 4096;
  model.truncation = Truncation::drop;
  model.initial = monodisperse(model.size);
  const Run r = run(model, IntegratorMethod::automatic, 1e-8);
  CHECK(r.stats.stiff_from == -1.0);
  CHECK(r.stats.linear_iterations == 0);
  const std::vector<double> times{1.0, 10.0, 100.0};
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double t = times[i];
    CHECK(relative_error(r.moments[3 * i], 1.0 / (1.0 + t)) <= 1e-7);
    CHECK(relative_error(r.moments[3 * i + 1], 1.0 + 2.0 * t) <= 1e-7);
    CHECK(relative_error(r.moments[3 * i + 2], 1.0 + 6.0 * t + 6.0 * t * t) <= 1e-7);
  }
}

TEST_CASE("an unknown method or ERK table is refused naming the key", "[cvode][input]") {
  CHECK_THROWS_WITH(integrator_method_from_name("rk45"), Catch::Contains("method") && Catch::Contains("erk, auto"));
  IntegratorOptions options;
  options.rtol = 2.0;
  options.method = IntegratorMethod::erk;
  CHECK_THROWS_WITH(options.validate(), Catch::Contains("rtol"));
}

// The low-rank kernel's default tolerance follows the run's: 10 rtol (within [1e-12, 1e-5]), which the
// factorisation meets with room to spare, and the moments still meet rtol: against BDF at rtol 1e-11 with the
// kernel at 1e-12, within 10 rtol (the tolerance tests' bound; measured 0.1-0.6 rtol at N = 2000).
TEST_CASE("the low-rank kernel's default tolerance is 10 rtol, and the run still meets rtol", "[cvode][lowrank]") {
  IntegratorOptions options;
  options.rtol = 1e-8;
  CHECK(options.effective_lowrank_tolerance() == Approx(1e-7));
  options.rtol = 1e-14;
  CHECK(options.effective_lowrank_tolerance() == 1e-12);
  options.rtol = 1e-3;
  CHECK(options.effective_lowrank_tolerance() == 1e-5);
  options.lowrank_tolerance = 1e-9;  // an explicit request wins
  CHECK(options.effective_lowrank_tolerance() == 1e-9);

  const AggregationModel model = ballistic();
  const Run reference = run(model, IntegratorMethod::bdf_gmres, 1e-11);
  for (const IntegratorMethod method : {IntegratorMethod::automatic, IntegratorMethod::erk}) {
    const Run loose = run(model, method, 1e-8);
    INFO(to_string(method) << ": kernel rank " << loose.stats.kernel_rank << ", kernel error " << loose.stats.kernel_relative_error);
    CHECK(loose.stats.kernel_relative_error <= 1e-7);
    // Fewer terms than a factorisation to rtol itself (N = 1000: rank 16 against 17).
    CHECK(loose.stats.kernel_rank < run(model, method, 1e-8, 1e-8).stats.kernel_rank);
    for (std::size_t i = 0; i < reference.moments.size(); ++i)
      CHECK(relative_error(loose.moments[i], reference.moments[i]) <= 1e-7);
  }
}

TEST_CASE("BDF steps grow in a steady state next to a stable focus (stability limit detection)", "[erk]") {
  // Ballistic kernel, λ = 0.1, N = 5000, cutoff: the run is at its steady state (a stable focus) by t ~ 50. Without
  // CVODE's stability limit detection BDF at orders 3–5 sat on the boundary of its stability region, a constant
  // step 0.076 whatever rtol (0.060 at 1e-8, 0.069 at 1e-4): 4139 steps to t = 300. With it: 451. Bound 1500.
  // (auto, whose BDF starts afresh at its switch at t = 4.3, still takes 2648, against 3194 without: not bounded
  // here.) The state each reaches is the same: M0 within 1e-5 of the run at rtol 1e-8.
  const AggregationModel model = ballistic(0.1, 5000);
  auto final_m0 = [&](IntegratorMethod method, double rtol, long& steps) {
    IntegratorOptions options;
    options.method = method;
    options.rtol = rtol;
    double m0 = 0;
    steps = integrate(model, std::vector<double>{300.0}, options, [&](double, std::span<const double> n, double) { m0 = moment(n, 0.0); }).steps;
    return m0;
  };
  long steps = 0, reference_steps = 0, auto_steps = 0;
  const double reference = final_m0(IntegratorMethod::bdf_gmres, 1e-8, reference_steps);
  const double m0 = final_m0(IntegratorMethod::bdf_gmres, 1e-6, steps);
  const double m0_auto = final_m0(IntegratorMethod::automatic, 1e-6, auto_steps);
  INFO("steps: " << steps << " (auto " << auto_steps << ", rtol 1e-8: " << reference_steps << ")");
  CHECK(steps < 1500);
  CHECK(std::abs(m0 / reference - 1) < 1e-5);
  CHECK(std::abs(m0_auto / reference - 1) < 1e-5);
}

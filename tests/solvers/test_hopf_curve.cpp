// λ_crit(a) converged in N (solvers/hopf_curve.hpp) against the N = 8192 values of locate_hopf, the
// geometric convergence in N that its error bar relies on, and the bracket stepping of locate_hopf.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "analysis/input_error.hpp"
#include "solvers/hopf_curve.hpp"

using namespace aggkit;

namespace {

AggregationModel cutoff_model(std::size_t N) {
  AggregationModel model;
  model.size = N;
  model.truncation = Truncation::cutoff;
  model.initial = monodisperse(N);
  return model;
}

}  // namespace

TEST_CASE("hopf_curve reproduces the N = 8192 lambda_crit within its error bars", "[stability][hopf][hopf_curve]") {
  // References: locate_hopf at N = 8192, Brent bracket 1e-3 (bench/results/RESULTS.md): λ_crit(0.95) = 0.0126706
  // (bracket 6.3e-6; N = 16384 gives the same digits), λ_crit(0.9) = 0.00962022 (bracket 4.8e-6). The
  // converged search stops at N = 1024 … 2048 here. Its claim: the value at its largest N lies within
  // change · λ (the N/2 → N change, its truncation error bar) plus its Brent bracket of the true λ_crit;
  // with the reference's own bracket added, that is what is checked. The claim fails if the truncation
  // error did not shrink geometrically (the last change would then understate it) or the continuation
  // in a started a point on the wrong crossing.
  const std::vector<double> as{0.95, 0.9};
  const std::vector<double> reference{0.0126706, 0.00962022}, reference_bracket{6.3e-6, 4.8e-6};
  HopfCurveOptions options;
  const std::vector<ConvergedHopfPoint> curve = hopf_curve(cutoff_model(512), as, 0.0125, 512, options);
  REQUIRE(curve.size() == 2);
  for (std::size_t i = 0; i < curve.size(); ++i) {
    const ConvergedHopfPoint& p = curve[i];
    INFO("a = " << p.a << ", N = " << p.size << ", lambda_crit = " << p.lambda_crit << ", change " << p.change << ", "
                << p.note);
    REQUIRE(p.converged);
    CHECK(p.change <= options.convergence);
    CHECK(p.size <= 4096);
    CHECK(std::abs(p.lambda_crit - reference[i]) <= p.change * p.lambda_crit + p.bracket + reference_bracket[i]);
    CHECK(p.bracket <= options.relative_tolerance * p.lambda_crit * 1.01);
    // The period of the crossing pair: 2π/ω = 26.44 (a = 0.95) and 37.77 (a = 0.9) at N = 8192.
    CHECK(2 * M_PI / p.omega == Approx(i == 0 ? 26.44 : 37.77).epsilon(2e-3));
  }
}

TEST_CASE("lambda_crit converges geometrically in N (a = 1)", "[stability][hopf][hopf_curve]") {
  // With the tail n_k ∝ k^{-a} e^{-ck}, c ≈ 0.65 λ, each doubling of N should shrink the truncation error
  // of λ_crit by a large factor once c N exceeds a few. Forced to double from N = 256 until the change is
  // ≤ 1e-4 (Brent to 1e-5, so the changes are resolved to ~2e-5; N = 256 has no steady state near λ_crit,
  // c N ≈ 2.5): the changes must fall monotonically (each at most half the previous: geometric, so the last
  // change bounds what further doublings can add), and the final value must sit at the N = 8192 one,
  // 0.0153804 (bracket 2.9e-6), within its error bar.
  HopfCurveOptions options;
  options.min_size = 256;
  options.size_per_inverse_lambda = 0.0;
  options.convergence = 1e-4;
  options.relative_tolerance = 1e-5;
  options.max_size = 4096;
  const ConvergedHopfPoint p = locate_hopf_converged(cutoff_model(256), 1.0, 0.015, 256, options);
  INFO(p.note);
  std::vector<double> found;
  for (std::size_t i = 0; i < p.by_size.size(); ++i) {
    INFO("N = " << p.sizes[i] << ": " << p.by_size[i].lambda_crit << " " << p.by_size[i].note);
    if (p.by_size[i].found) found.push_back(p.by_size[i].lambda_crit);
  }
  REQUIRE(found.size() >= 3);
  for (std::size_t i = 2; i < found.size(); ++i) {
    INFO("step " << i);
    CHECK(std::abs(found[i] - found[i - 1]) <= 0.5 * std::abs(found[i - 1] - found[i - 2]) + 2e-5 * found[i]);
  }
  REQUIRE(p.converged);
  CHECK(p.by_size.front().note.find("no steady state") != std::string::npos);  // N = 256: too short
  CHECK(std::abs(p.lambda_crit - 0.0153804) <= p.change * p.lambda_crit + p.bracket + 2.9e-6);
}

TEST_CASE("locate_hopf steps a bracket that misses the crossing", "[stability][hopf]") {
  // a = 0.95, N = 1024: λ_crit = 0.01267. [0.005, 0.006] lies below it (both ends unstable).
  AggregationModel model = cutoff_model(1024);
  HopfOptions options;
  const HopfPoint stuck = locate_hopf(model, 0.95, 0.005, 0.006, 1e-2, options);
  CHECK_FALSE(stuck.found);
  CHECK(stuck.note.find("unstable at lambda_hi") != std::string::npos);
  options.bracket_steps = 8;  // 0.006 · 1.2^5 = 0.0149 > 0.01267: five steps reach it
  const HopfPoint p = locate_hopf(model, 0.95, 0.005, 0.006, 1e-2, options);
  INFO(p.note);
  REQUIRE(p.found);
  CHECK(std::abs(p.lambda_crit - 0.0126719) <= p.lambda_tolerance);  // the N = 1024 value (test_stability.cpp)
  CHECK(p.note.find("bracket stepped") != std::string::npos);
  CHECK(p.steady_state.size() == 1024);
}

TEST_CASE("hopf_curve bad input", "[stability][hopf_curve][input]") {
  const AggregationModel model = cutoff_model(64);
  HopfCurveOptions options;
  CHECK_THROWS_AS(locate_hopf_converged(model, 0.9, 0.0, 64, options), InputError);
  options.convergence = 0.0;
  CHECK_THROWS_AS(locate_hopf_converged(model, 0.9, 0.01, 64, options), InputError);
  options = HopfCurveOptions{};
  options.max_size = options.min_size;
  CHECK_THROWS_AS(locate_hopf_converged(model, 0.9, 0.01, 64, options), InputError);
  options = HopfCurveOptions{};
  options.relative_tolerance = 0.5;
  CHECK_THROWS_AS(hopf_curve(model, std::vector<double>{0.9}, 0.01, 64, options), InputError);
}

TEST_CASE("locate_hopf from a start at another (a, λ) follows its branch to the same lambda_crit", "[stability][hopf]") {
  // Graded grid K = 64, r = 1.04, N = 2^33, cutoff, brownian a = 0.6: the branch's Hopf point is at
  // λ = 5.7221e-8, ω = 1.2486e-6 with four-moment shares (a direct locate_hopf from its own steady state; the
  // converged curve on r = 1.02 gives 5.7216e-8, changes N 6e-7, 2K 5e-7, (r-1)/2 1.3e-5,
  // bench/results/RESULTS.md). Three-moment shares gave 5.7457e-8, ω = 1.2525e-6 on this grid.
  // The start is the steady state at (a, λ) = (0.61, 3e-7), far from the bracket [5e-8, 7e-8]: the
  // continuation must end at the requested (0.6, λ) and find the same crossing (a path that stayed at
  // a = 0.61 finds no crossing in the bracket: checked by breaking it). This checks where the path ends, not
  // that a single jump from this start would fail (from here it does not).
  AggregationModel model;
  model.size = std::size_t(1) << 33;
  model.truncation = Truncation::cutoff;
  model.initial = monodisperse(1);
  model.grid.resolved = 64;
  model.grid.ratio = 1.04;
  AggregationModel at_start = model;
  at_start.kernel = Kernel::brownian(0.61);
  at_start.lambda = ShatteringRate::constant(3e-7);
  const SteadyStateResult start = solve_steady_state(at_start);
  REQUIRE(start.converged);
  HopfOptions options;
  options.start = start.n;
  options.start_sizes = model.pivots();
  options.start_a = 0.61;
  options.start_lambda = 3e-7;
  const HopfPoint p = locate_hopf(model, 0.6, 5e-8, 7e-8, 1e-3, options);
  INFO(p.note);
  REQUIRE(p.found);
  CHECK(p.lambda_crit == Approx(5.7221e-8).epsilon(2e-3));  // the Brent bracket 1e-3 plus the reference's
  CHECK(p.omega == Approx(1.2486e-6).epsilon(2e-3));
  CHECK(p.steady_lambda >= p.lambda_crit);  // the stable end's state
}

TEST_CASE("locate_hopf steps up from a bracket with no positive steady state", "[stability][hopf]") {
  // a = 0.95, N = 1024: λ_crit = 0.01267. At λ ~ 2e-5 (λN = 0.02) the truncated system has no positive root,
  // so neither end of [2e-5, 2.2e-5] can be evaluated; the bracket steps up in doubling steps until one can.
  AggregationModel model = cutoff_model(1024);
  HopfOptions options;
  const HopfPoint none = locate_hopf(model, 0.95, 2e-5, 2.2e-5, 1e-2, options);
  INFO(none.note);
  CHECK_FALSE(none.found);
  CHECK(none.note.find("no steady state at lambda_hi") != std::string::npos);
  CHECK(none.lambda_no_steady == Approx(2.2e-5));
  options.bracket_steps = 30;
  const HopfPoint p = locate_hopf(model, 0.95, 2e-5, 2.2e-5, 1e-2, options);
  INFO(p.note);
  CHECK(p.note.find("no steady state below lambda") != std::string::npos);
  REQUIRE(p.found);
  CHECK(std::abs(p.lambda_crit - 0.0126719) <= p.lambda_tolerance);
}

// Real CVODE runs classified by the scan: the published regimes of the Brownian-type kernel with
// shattering ([Kalinov2022, Sec. 5.2]: a = 0.95, λ = 0.01 oscillates steadily; a = 0.9, λ = 0.01 converges to the
// steady state).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "validation/scan/scan_plan.hpp"
#include "validation/scan/scan_point.hpp"

using namespace aggkit;

namespace {

// N = 2048 is the smallest power of two with the published regimes: at N = 1024 the a = 0.95 oscillation
// decays (its amplitude fell by a third between t = 300 and 1500), while at N = 2048 and 4096 M0 swings
// between 0.0804 and 0.2308-0.2311 from t ~ 500 on, as at N = 8192 (0.080-0.231,
// validation/scenes/brownian-oscillation.toml). t = 1000: the transient is over by t ~ 500, and the tail
// (t in [500, 1000]) holds ~14 cycles. About 4 s per point on one core.
const char* const scene = R"(
name = "published-regimes"
[model]
kernel = { name = "brownian", a = 0.9 }
size = 2048
truncation = "drop"
[time]
end = 1000.0
every = 1.0
[[engine]]
name = "cvode"
rtol = 1e-6
[scan]
a = [0.9, 0.95]
lambda = [0.01]
)";

// The scan's command-line test grid (K = 8, r = 1.6, fixed pivots, N = 2^20) at a = 0.9, λ = 0.001: an unstable
// focus around which shooting finds a stable cycle.
std::string coarse_graded_scene() {
  std::string graded = scene;
  graded.replace(graded.find("size = 2048"), 11, "size = 1048576\ngrid = { resolved = 8, ratio = 1.6, scheme = \"fixed-pivot\" }");
  graded.replace(graded.find("a = [0.9, 0.95]"), 15, "a = [0.9]");
  graded.replace(graded.find("lambda = [0.01]"), 15, "lambda = [0.001]");
  return graded;
}

}  // namespace

TEST_CASE("scan point: a = 0.95, lambda = 0.01 is sustained with the long run's swing and period") {
  const ScanPlan plan = parse_scan_plan(scene);
  const ScanRecord r = run_scan_point(plan, {1, 0.95, 0.01}, plan.size());
  CHECK(r.regime == "sustained");
  CHECK(r.converged);
  CHECK(r.cycles >= 10);
  // The N = 8192, rtol 1e-8 run swings between 0.080 and 0.231 (3 digits: ±0.001 each) with a period of
  // about 33 (measured over t in [500, 3000]).
  CHECK(2 * r.amplitude == Approx(0.231 - 0.080).margin(0.002));
  CHECK(r.period == Approx(33.5).margin(1.0));
  CHECK(std::abs(r.decay_rate) * 500 < 0.02);  // the envelope changes by < 2 % over the tail
  INFO("rightmost " << r.rightmost_real << " +- " << r.rightmost_imag << " i");
  CHECK(r.regime_stability == "sustained");  // the steady state is unstable
  CHECK(r.agree == "yes");
}

TEST_CASE("scan point: a = 0.9, lambda = 0.01 is damped towards the steady state") {
  const ScanPlan plan = parse_scan_plan(scene);
  const ScanRecord r = run_scan_point(plan, {0, 0.9, 0.01}, plan.size());
  CHECK((r.regime == "damped" || r.regime == "steady"));
  CHECK(r.regime == "damped");  // at t = 1000 the swing is still ~10 % of the mean
  CHECK(r.converged);
  // The envelope decays by e^{-γ·500} over the tail; γ ~ 1e-3 (the amplitude fell from 0.041 to 0.007
  // between t ~ 350 and 1850 in a t = 2000 run, ratio 0.76 per 300 at the end: γ ≈ 9e-4).
  CHECK(r.decay_rate > 5e-4);
  CHECK(r.decay_rate < 3e-3);
  CHECK(r.decay_rate_error < 0.1 * r.decay_rate);
  INFO("rightmost " << r.rightmost_real << " +- " << r.rightmost_imag << " i, decay " << r.decay_rate << ", period " << r.period);
  CHECK(r.regime_stability == "damped");
  CHECK(r.agree == "yes");
  // The run has reached the steady state: the tail's mean is 0.9 % from the steady M0 (steady_match 5 %).
  CHECK(std::abs(r.mean - r.mean_steady) < 0.02 * r.mean_steady);
  // Independent check of the time series by the linearisation (solvers/stability.hpp): the damped mode's
  // period is 2π/Im μ up to the nonlinear frequency shift of a swing still ~10 % of the mean (O(10 %²) ~ 1 %:
  // 2 % allowed), and the envelope decays at least as fast as the linear rate -Re μ (nonlinear damping adds
  // to it at that amplitude; measured 1.15e-3 against 8.1e-4).
  CHECK(r.period == Approx(2 * std::acos(-1.0) / r.rightmost_imag).epsilon(0.02));
  CHECK(r.decay_rate > -r.rightmost_real);
  CHECK(r.decay_rate < -2 * r.rightmost_real);
}

TEST_CASE("scan point: a relaxation without a steady state to confirm it is unresolved, not damped") {
  // a = 0.95, λ = 1e-6 (λ_crit = 0.0127: the steady state is unstable) on N = 2048: the steady tail needs
  // N ≥ 8/λ = 8·10^6, so no steady state is found, and by t = 1000 the run shows only the coarsening of
  // nearly pure aggregation, M0 decaying monotonically — which the time series alone would call damped.
  const ScanPlan plan = parse_scan_plan(scene);
  const ScanRecord r = run_scan_point(plan, {2, 0.95, 1e-6}, plan.size());
  INFO(r.regime << ": " << r.note);
  CHECK(r.regime_stability.empty());
  CHECK(r.regime == "unresolved");
  CHECK_THAT(r.note, Catch::Contains("no steady state was found"));
}

TEST_CASE("scan point: the progress line's outcome names only the numbers the regime has") {
  ScanRecord steady;
  steady.regime = "steady";
  CHECK(outcome_summary(steady) == "steady");
  ScanRecord damped;  // a monotone relaxation: decay rate, no period
  damped.regime = "damped";
  damped.decay_rate = 0.0042;
  CHECK(outcome_summary(damped) == "damped, decay rate 0.0042");
  damped.period = 48.7;  // a damped oscillation
  CHECK(outcome_summary(damped) == "damped, decay rate 0.0042 (period 48.7)");
  ScanRecord sustained;
  sustained.regime = "sustained";
  sustained.period = 52.1;
  sustained.amplitude = 0.0123;
  CHECK(outcome_summary(sustained) == "sustained, period 52.1, amplitude 0.0123");
  for (const ScanRecord* r : {&steady, &damped, &sustained}) CHECK(outcome_summary(*r).find("nan") == std::string::npos);
}

TEST_CASE("scan point: a relaxation that ends far from its steady state is unresolved, not damped") {
  // a = 0.6, λ = 1e-4 on a graded grid that holds the steady tail (N = 2^40 ≫ 8/λ): the steady state exists
  // and is stable, but it is reached only after times ~1/λ; by t = 2000 the run shows the coarsening of
  // nearly pure aggregation (M0 ≈ 5e-4, falling monotonically), not the approach to the steady M0 ≈ 9.4e-3.
  const char* const text = R"(
name = "slow-relaxation"
[model]
kernel = { name = "brownian", a = 0.6 }
size = 1099511627776
grid = { resolved = 64, ratio = 1.05 }
truncation = "drop"
[time]
end = 2000.0
every = 2.0
[[engine]]
name = "cvode"
method = "bdf-gmres"
rtol = 1e-6
[scan]
a = [0.6]
lambda = [1e-4]
)";
  const ScanPlan plan = parse_scan_plan(text);
  const ScanRecord r = run_scan_point(plan, {0, 0.6, 1e-4}, plan.size());
  INFO(r.regime << ": " << r.note);
  CHECK(r.regime_stability == "damped");  // the steady state is there and stable
  CHECK(r.mean_steady == Approx(9.4e-3).epsilon(0.02));
  CHECK(r.mean < 0.1 * r.mean_steady);
  CHECK(r.regime == "unresolved");
  CHECK_THAT(r.note, Catch::Contains("was damped in the run; the run ends before reaching the steady state"));
  // The time series' own verdict, as a refined repeat keeps it (it is compared by its class).
  const ScanRecord raw = run_scan_point(plan, {0, 0.6, 1e-4}, plan.size(), {}, false);
  CHECK(raw.regime == "damped");
}

TEST_CASE("scan point: with confirm_run the run's length comes from the spectrum, and a long one is not run") {
  // a = 0.9, λ = 0.001 on the coarse graded grid of the scan's command-line test (K = 8, r = 1.6, fixed
  // pivots, N = 2^20), where the steady state is an unstable focus and shooting finds a stable cycle. The
  // cycle is shot first; the confirmation then runs 1/λ + 12/Re μ + 8 shot periods, not the scene's t = 1000,
  // and classifies the last 8 periods: sustained with the shot cycle's period (the time series' period is the
  // mean crossing interval of a series sampled 25 times per period: 1 % allowed).
  const std::string graded = coarse_graded_scene();
  std::string text = graded;
  text += "confirm_run = 20000.0\n";
  const ScanPlan plan = parse_scan_plan(text);
  const ScanRecord r = run_scan_point(plan, {0, 0.9, 0.001}, plan.size());
  INFO(r.regime << " / " << r.verdict << ": " << r.note);
  REQUIRE(r.regime_stability == "sustained");
  REQUIRE(std::isfinite(r.cycle_period));
  const double expected = 1 / 0.001 + 12 / r.rightmost_real + 8 * r.cycle_period;
  CHECK(r.run_end == Approx(expected).epsilon(1e-9));
  CHECK(r.run_end != Approx(1000.0));
  CHECK(r.regime == "sustained");
  CHECK(r.verdict == "sustained");
  CHECK(r.agree == "yes");
  CHECK(r.period == Approx(r.cycle_period).epsilon(0.01));

  // The same point with a budget below that length: no confirmation; the cycle search's own run (off the
  // steady state, its second half classified) stands as the point's run, and says so.
  std::string tight = graded;
  tight += "confirm_run = 1500.0\n";
  const ScanPlan short_plan = parse_scan_plan(tight);
  const ScanRecord s = run_scan_point(short_plan, {0, 0.9, 0.001}, short_plan.size());
  INFO(s.regime << " / " << s.verdict << ": " << s.note);
  CHECK(s.regime == "sustained");
  CHECK(s.verdict == "sustained");
  CHECK(s.agree == "yes");
  CHECK(s.period == Approx(r.cycle_period).epsilon(0.01));
  CHECK(s.run_end != Approx(r.run_end));
  CHECK_THAT(s.note, Catch::Contains("a confirmation needs t = ") && Catch::Contains("beyond confirm_run = 1500") &&
                         Catch::Contains("the run is the cycle search's from the steady state"));

  // A stable focus (a = 0.9, λ = 0.012: no cycle search): the run relaxes for 1/λ + max(6/|Re μ|, 16 periods)
  // and is classified over as long again, where it has relaxed (steady, or the decay converged).
  std::string stable = graded;
  stable.replace(stable.find("lambda = [0.001]"), 16, "lambda = [0.012]");
  const ScanPlan relax_plan = parse_scan_plan(stable + "confirm_run = 20000.0\n");
  const ScanRecord d = run_scan_point(relax_plan, {0, 0.9, 0.012}, relax_plan.size());
  INFO(d.regime << " / " << d.verdict << ": " << d.note);
  REQUIRE(d.regime_stability == "damped");
  const double relaxation = 1 / 0.012 + std::max(6 / -d.rightmost_real, 16 * 2 * M_PI / d.rightmost_imag);
  CHECK(d.run_end == Approx(2 * relaxation).epsilon(1e-9));
  CHECK(is_relaxing(d));
  CHECK(d.verdict == "damped");
  CHECK(d.agree == "yes");

  // The same point with a budget below its confirmation (1/λ = 83 alone is beyond 50): not run, the length
  // it would need in the note, the verdict from the spectrum.
  stable += "confirm_run = 50.0\n";
  const ScanPlan stable_plan = parse_scan_plan(stable);
  const ScanRecord f = run_scan_point(stable_plan, {0, 0.9, 0.012}, stable_plan.size());
  INFO(f.regime << " / " << f.verdict << ": " << f.note);
  CHECK(f.regime == "not-run");
  CHECK(std::isnan(f.run_end));
  CHECK(f.verdict == "damped");
  CHECK(f.agree.empty());
  CHECK_THAT(f.note, Catch::Contains("a confirmation needs t = ") && Catch::Contains("beyond confirm_run = 50"));
}

TEST_CASE("scan point: confirm_run without stability is refused with the key") {
  std::string text = scene;
  text += "stability = false\nconfirm_run = 5000.0\n";
  try {
    parse_scan_plan(text);
    FAIL("accepted confirm_run without stability");
  } catch (const std::exception& e) {
    CHECK_THAT(e.what(), Catch::Contains("scan.confirm_run") && Catch::Contains("stability = true"));
  }
  std::string negative = scene;
  negative += "confirm_run = -1.0\n";
  CHECK_THROWS_WITH(parse_scan_plan(negative), Catch::Contains("scan.confirm_run"));
}

TEST_CASE("scan point: a cycle search beyond cycle_steps stops and says so, and a bad cycle_steps is refused") {
  // The sustained point of the confirm_run test (a = 0.9, λ = 0.001, K = 8, r = 1.6, fixed pivots): its search
  // run to t = 1000 takes about a thousand CVODE steps. With 100 allowed it stops; the point then has no cycle
  // and no run (confirm_run below its confirmation), so it is "unstable", and its note names the budget.
  const std::string graded = coarse_graded_scene();
  const ScanPlan plan = parse_scan_plan(graded + "confirm_run = 1500.0\ncycle_steps = 100\n");
  CHECK(plan.cycle_steps == 100);
  const ScanRecord r = run_scan_point(plan, {0, 0.9, 0.001}, plan.size());
  INFO(r.regime << " / " << r.verdict << ": " << r.note);
  CHECK(r.regime_stability == "sustained");
  CHECK(std::isnan(r.cycle_period));
  CHECK(r.verdict == "unstable");
  CHECK_THAT(r.note, Catch::Contains("needs more than cycle_steps = 100 steps"));

  CHECK_THROWS_WITH(parse_scan_plan(graded + "cycle_steps = 10\n"), Catch::Contains("scan.cycle_steps"));
  CHECK_THROWS_WITH(parse_scan_plan(graded + "cycle_steps = 2.5\n"), Catch::Contains("scan.cycle_steps"));
}

TEST_CASE("scan point: where the growth off the steady state is beyond cycle_run, the search starts on the Hopf normal form's cycle") {
  // The sustained point of the confirm_run test. Its cycle is first found the usual way (growth off the steady
  // state over 24/Re μ); then cycle_run is set between the normal-form start's need (16 periods + ln(1e3)/(2 Re μ))
  // and the growth's: the search must start on the normal form's cycle and find the same cycle.
  const std::string graded = coarse_graded_scene();
  const ScanPlan plan = parse_scan_plan(graded + "confirm_run = 1500.0\n");
  const ScanRecord r = run_scan_point(plan, {0, 0.9, 0.001}, plan.size());
  INFO(r.note);
  REQUIRE(std::isfinite(r.cycle_period));
  const double re = r.rightmost_real, period = 2 * M_PI / r.rightmost_imag;
  const double growth = std::max({1000.0, 16 * period, 24 / re});
  const double near = std::max(1000.0, 16 * period + std::log(1e3) / (2 * re));
  INFO("Re mu " << re << ", growth run " << growth << ", normal-form run " << near);
  REQUIRE(near < 0.9 * growth);
  const double budget = 0.5 * (near + growth);
  const ScanPlan near_plan = parse_scan_plan(graded + "confirm_run = 1500.0\ncycle_run = " + std::to_string(budget) + "\n");
  const ScanRecord s = run_scan_point(near_plan, {0, 0.9, 0.001}, near_plan.size());
  INFO(s.note);
  CHECK_THAT(s.note, Catch::Contains("the cycle search starts on the Hopf normal form's cycle"));
  REQUIRE(std::isfinite(s.cycle_period));
  CHECK(s.cycle_period == Approx(r.cycle_period).epsilon(1e-3));
  CHECK(s.cycle_stable == "yes");
  CHECK(s.verdict == "sustained");
}

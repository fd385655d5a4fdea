// Oscillation classification on synthetic signals whose regime, period, amplitude and decay rate are known
// exactly. (Real CVODE runs are classified in tests/validation/test_scan_point.cpp.)
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "analysis/input_error.hpp"
#include "tests/analysis/sampled_series.hpp"
#include "analysis/oscillation.hpp"

using namespace aggkit;

namespace {

using aggkit::testing::Series;
using aggkit::testing::sample;
using aggkit::testing::two_pi;

OscillationClassification classify(const Series& s, const OscillationCriteria& criteria = {}) {
  return classify_oscillation(s.t, s.x, criteria);
}

}  // namespace

TEST_CASE("oscillation: a pure sine is sustained with its period and amplitude") {
  // Period 33.3 sampled at Δt = 1 (as the scans sample M0): the parabolic refinement of the turning points
  // has error O((Δt/T)^4) ~ 1e-6 relative, so 1e-4 is a safe bound for period and amplitude.
  const double period = 33.3, amplitude = 0.3;
  const auto s = sample(1000, 1.0, [&](double t) { return 1.0 + amplitude * std::sin(two_pi * t / period + 0.4); });
  const auto c = classify(s);
  CHECK(c.regime == Regime::sustained);
  CHECK(c.converged);
  CHECK(c.period == Approx(period).epsilon(1e-4));
  CHECK(c.amplitude == Approx(amplitude).epsilon(1e-4));
  CHECK(c.mean == Approx(1.0).epsilon(1e-2));  // the tail is not a whole number of periods
  CHECK(std::abs(c.decay_rate) < 1e-6);
  CHECK(c.cycles >= 14);  // 500 / 33.3 = 15 cycles in the tail, less the partial ones at the ends
  CHECK(c.amplitude_change < 1e-4);
  CHECK(c.period_change < 1e-4);
}

TEST_CASE("oscillation: a damped sine is damped with its decay rate") {
  // x = 1 + 0.3 e^{-γt} sin(2πt/T): successive turning points of one kind are exactly e^{-γT} apart, so the
  // fitted envelope rate is γ up to the parabolic refinement error (~1e-4 relative at T/Δt = 20).
  const double gamma = 0.005, period = 20.0;
  const auto s = sample(600, 1.0, [&](double t) { return 1.0 + 0.3 * std::exp(-gamma * t) * std::sin(two_pi * t / period); });
  const auto c = classify(s);
  CHECK(c.regime == Regime::damped);
  CHECK(c.converged);
  CHECK(c.decay_rate == Approx(gamma).epsilon(1e-3));
  CHECK(c.decay_rate_error < 1e-3 * gamma);
  CHECK(c.period == Approx(period).epsilon(1e-3));
}

TEST_CASE("oscillation: a slowly growing oscillation is sustained but not converged") {
  const auto s = sample(800, 1.0, [&](double t) { return 1.0 + 0.01 * std::exp(0.004 * t) * std::sin(two_pi * t / 25); });
  const auto c = classify(s);
  CHECK(c.regime == Regime::sustained);
  CHECK_FALSE(c.converged);
  CHECK(c.decay_rate == Approx(-0.004).epsilon(1e-2));
  CHECK(c.note.find("growing") != std::string::npos);
}

TEST_CASE("oscillation: a decay slower than the drift tolerance over the tail counts as sustained") {
  // γ W = 1e-5 × ~480 = 0.5 % < drift_tolerance (2 %): within the resolution of a finite window.
  const auto s = sample(1000, 1.0, [&](double t) { return 1.0 + 0.2 * std::exp(-1e-5 * t) * std::sin(two_pi * t / 30); });
  const auto c = classify(s);
  CHECK(c.regime == Regime::sustained);
  CHECK(c.decay_rate == Approx(1e-5).epsilon(2e-2));
  // The same decay over a 10x longer window (γ W = 5 %) is resolved as damped.
  const auto longer = sample(10000, 1.0, [&](double t) { return 1.0 + 0.2 * std::exp(-1e-5 * t) * std::sin(two_pi * t / 30); });
  CHECK(classify(longer).regime == Regime::damped);
}

TEST_CASE("oscillation: relaxation to a constant is damped (monotone) or steady once relaxed") {
  // x = 2 - e^{-γt}: increments e^{-γt}(1 - e^{-γΔt}) decay exactly at γ.
  const auto relaxing = sample(400, 1.0, [](double t) { return 2.0 - std::exp(-0.02 * t); });
  const auto c = classify(relaxing);
  CHECK(c.regime == Regime::damped);
  CHECK(c.decay_rate == Approx(0.02).epsilon(1e-9));
  CHECK(std::isnan(c.period));
  CHECK(c.note == "monotone relaxation");
  // Relaxed to 2e-9 relative over the tail: steady.
  const auto relaxed = sample(400, 1.0, [](double t) { return 2.0 - std::exp(-0.1 * t); });
  const auto r = classify(relaxed);
  CHECK(r.regime == Regime::steady);
  CHECK(r.mean == Approx(2.0).epsilon(1e-8));
  // A linear drift neither oscillates nor relaxes: damped (no persistent oscillation) but not converged.
  const auto drifting = sample(400, 1.0, [](double t) { return 1.0 + 1e-3 * t; });
  const auto d = classify(drifting);
  CHECK(d.regime == Regime::damped);
  CHECK_FALSE(d.converged);
  CHECK(std::abs(d.decay_rate) < 1e-9);
  CHECK(d.note.find("drift") != std::string::npos);
}

TEST_CASE("oscillation: noise") {
  std::mt19937_64 generator(12345);
  std::normal_distribution<double> normal(0.0, 1.0);
  SECTION("integrator-level noise on a constant is steady") {
    const auto s = sample(500, 1.0, [&](double) { return 5.0 * (1 + 1e-6 * normal(generator)); });
    CHECK(classify(s).regime == Regime::steady);
  }
  SECTION("a sine with 1 % noise keeps its period and amplitude") {
    // Noise σ = 1 % of the amplitude shifts each turning point's value by ~σ and its time by ~sqrt(σ) T/2π;
    // averaged over the last 4 cycles the amplitude is within ~2σ and the period within ~1 %.
    const auto s = sample(1000, 1.0, [&](double t) { return 1.0 + 0.3 * std::sin(two_pi * t / 40) + 0.003 * normal(generator); });
    const auto c = classify(s);
    CHECK(c.regime == Regime::sustained);
    CHECK(c.period == Approx(40).epsilon(1e-2));
    CHECK(c.amplitude == Approx(0.3).epsilon(2e-2));
  }
  SECTION("white noise is irregular, not an oscillation") {
    const auto s = sample(1000, 1.0, [&](double) { return 10.0 + normal(generator); });
    const auto c = classify(s);
    CHECK(c.regime == Regime::irregular);
    CHECK(c.note.find("scatter") != std::string::npos);
  }
}

TEST_CASE("oscillation: too few cycles in the tail give a tentative verdict") {
  const auto s = sample(1000, 1.0, [](double t) { return 1.0 + 0.3 * std::sin(two_pi * t / 200); });
  const auto c = classify(s);
  CHECK(c.regime == Regime::sustained);
  CHECK_FALSE(c.converged);
  CHECK(c.note.find("cycles in the tail") != std::string::npos);
}

TEST_CASE("oscillation: bad series and criteria are rejected") {
  const auto s = sample(100, 1.0, [](double t) { return std::sin(t); });
  std::vector<double> uneven = s.t;
  uneven[10] += 0.5;
  CHECK_THROWS_AS(classify_oscillation(uneven, s.x), InputError);
  CHECK_THROWS_AS(classify_oscillation(std::span(s.t).first(50), s.x), InputError);
  std::vector<double> nan_x = s.x;
  nan_x[3] = std::nan("");
  CHECK_THROWS_WITH(classify_oscillation(s.t, nan_x), Catch::Contains("series.x[3]"));
  const auto short_series = sample(20, 1.0, [](double t) { return t; });
  CHECK_THROWS_WITH(classify_oscillation(short_series.t, short_series.x), Catch::Contains("at least 16 samples"));
  OscillationCriteria criteria;
  criteria.tail_fraction = 0;
  CHECK_THROWS_WITH(classify_oscillation(s.t, s.x, criteria), Catch::Contains("oscillation.tail_fraction"));
}

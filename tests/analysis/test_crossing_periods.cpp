// Periods from mid-range crossings and whether they settled, on synthetic series whose period and modulation
// are known exactly. (The scan's cycle columns use them on CVODE runs: tests/apps/test_scan_cli.cpp.)
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <span>
#include <vector>

#include "analysis/crossing_periods.hpp"
#include "analysis/input_error.hpp"
#include "tests/analysis/sampled_series.hpp"

using namespace aggkit;

namespace {

using aggkit::testing::Series;
using aggkit::testing::sample;
using aggkit::testing::two_pi;

// Whether the last three periods agree to 2e-3 of T (what settled on three periods would accept).
bool last_three_agree(const CrossingPeriods& c, double T) {
  const std::span<const double> last3 = std::span<const double>(c.periods).last(3);
  const auto [lo, hi] = std::minmax_element(last3.begin(), last3.end());
  return *hi - *lo <= 2e-3 * T;
}

CycleSettlingVerdict settling_of(const Series& s) { return cycle_settling(crossing_periods(s.t, s.x), s.x); }

// A relaxation-like cycle of period T (a sharp pulse each period) whose phase is modulated by ε sin(2π t/(q T)):
// the crossings move by (ε T/2π) sin(2π t/(q T)), so the time between them varies by up to ±(ε/2π) 2 sin(π/q) T
// around T, recurring every q periods.
std::function<double(double)> modulated_pulses(double T, double epsilon, double q, double decay = 0.0) {
  return [=](double t) {
    const double phase = two_pi * t / T + epsilon * std::exp(-decay * t) * std::sin(two_pi * t / (q * T));
    return std::exp(4.0 * std::cos(phase));
  };
}

}  // namespace

TEST_CASE("crossing periods: a periodic pulse train settles on its period", "[unit][analysis]") {
  const double T = 837.0;
  const Series s = sample(12 * T, T / 400, modulated_pulses(T, 0.0, 1.0));
  const CrossingPeriods c = crossing_periods(s.t, s.x);
  REQUIRE(c.crossings.size() == 12);
  // Linear interpolation between samples T/400 apart on a pulse: within 1e-4 T.
  for (double p : c.periods) CHECK(std::abs(p - T) < 1e-4 * T);
  const CycleSettlingVerdict v = cycle_settling(c, s.x);
  CHECK(v.settling == CycleSettling::settled);
  CHECK(std::abs(v.period - T) < 1e-4 * T);
  CHECK(v.spread < 2e-4);
  CHECK(v.periods == 11);
}

TEST_CASE("crossing periods: a burst narrower than the outputs settles on its period and its troughs", "[unit][analysis]") {
  // A smooth cycle 1.5 - 0.5 cos φ with a spike 0.6 exp(300 (cos(φ - π) - 1)) on its top, T/109 wide, sampled
  // 50.3 times a period: the crossings of the mid-range (on the smooth flank) give the period, while the
  // sampled heights of the spike, and the parabolas through them, drift from period to period by more than the
  // 5e-3 the peaks may differ. Runs of 12 … 14 periods: each settled.
  const double T = 9487.0;
  const auto spiked = [&](double t) {
    const double phi = two_pi * t / T;
    return 1.5 - 0.5 * std::cos(phi) + 0.6 * std::exp(300.0 * (std::cos(phi - two_pi / 2) - 1.0));
  };
  for (double end = 12 * T; end <= 14 * T; end += T / 8) {
    const Series s = sample(end, T / 50.3, spiked);
    const CrossingPeriods c = crossing_periods(s.t, s.x);
    REQUIRE(c.periods.size() >= 10);
    const CycleSettlingVerdict v = cycle_settling(c, s.x);
    INFO("end " << end / T << " T: " << to_string(v.settling));
    CHECK(v.settling == CycleSettling::settled);
    CHECK(std::abs(v.period - T) < 1e-3 * T);
  }
}

TEST_CASE("crossing periods: a quasi-periodic modulation that persists is unsettled, with its mean period", "[unit][analysis]") {
  // The period modulated by about ±2 % and recurring every 4.3 periods (as the sampling beat made the column's
  // periods at a = 0.9, λ = 1.78e-4 on 50 outputs a period).
  const double T = 1655.0, q = 4.3, epsilon = 0.1;
  const Series s = sample(24 * T, T / 50, modulated_pulses(T, epsilon, q));
  const CycleSettlingVerdict v = settling_of(s);
  REQUIRE(v.settling == CycleSettling::unsettled);
  CHECK(v.periods >= 22);
  // The mean is the first-to-last crossing time over the count: off by at most 2 (ε/2π) T / 22 = 1.4e-3 T.
  CHECK(std::abs(v.period - T) < 1.5e-3 * T);
  // Spread: up to 2 (ε/2π) 2 sin(π/q) = 0.042 peak to peak; a half samples most of it.
  CHECK(v.spread > 0.03);
  CHECK(v.spread < 0.045);
  CHECK(v.contraction > 0.9);
  CHECK(v.contraction < 1.1);
}

TEST_CASE("crossing periods: a persisting modulation whose last three periods agree by chance is still unsettled", "[unit][analysis]") {
  // A slow modulation (every 12 periods, ±0.8 %): near its turning points three consecutive periods agree to
  // 2e-3. Among the run lengths 24 T … 36 T some end there; each is unsettled, none settled.
  const double T = 1000.0;
  int lucky = 0;
  for (double end = 24 * T; end <= 36 * T; end += T / 4) {
    const Series s = sample(end, T / 50, modulated_pulses(T, 0.1, 12.0));
    const CrossingPeriods c = crossing_periods(s.t, s.x);
    if (last_three_agree(c, T)) ++lucky;
    const CycleSettlingVerdict v = cycle_settling(c, s.x);
    INFO("end " << end << ": " << to_string(v.settling));
    CHECK(v.settling == CycleSettling::unsettled);
  }
  CHECK(lucky >= 4);
}

TEST_CASE("crossing periods: a slow modulation is never settled from four periods, though three agree", "[unit][analysis]") {
  // Periods varying by ±1 % and recurring every 12.7 periods, runs of 6 … 18 periods: near the modulation's
  // turning points three consecutive periods agree to 2e-3 (within 0.17 of its range), four never (≥ 0.3 of it).
  const double T = 1654.0;
  int three_agree = 0;
  for (double end = 6 * T; end <= 18 * T; end += T / 8) {
    const Series s = sample(end, T / 400, modulated_pulses(T, 0.12, 12.7));
    const CrossingPeriods c = crossing_periods(s.t, s.x);
    if (last_three_agree(c, T)) ++three_agree;
    const CycleSettlingVerdict v = cycle_settling(c, s.x);
    INFO("end " << end << ": " << to_string(v.settling));
    CHECK(v.settling != CycleSettling::settled);
  }
  CHECK(three_agree >= 2);
}

TEST_CASE("crossing periods: a modulation that decays is settling, never unsettled", "[unit][analysis]") {
  // Decaying by e^{-0.5} a period: ρ ≈ 0.61, a cycle attracting well (|μ| ≈ 0.6): run on, not accepted.
  const double T = 1000.0;
  const Series s = sample(24 * T, T / 50, modulated_pulses(T, 0.3, 4.3, 0.5 / T));
  const CycleSettlingVerdict v = settling_of(s);
  // By the end the modulation is e^{-12} of 0.3 rad: the last periods agree far within 2e-3, so it settled.
  CHECK(v.settling == CycleSettling::settled);
  // Decaying by e^{-0.05} a period (ρ ≈ 0.95, as a cycle with |μ| = 0.95 would): unsettled. By e^{-0.2} (ρ ≈
  // 0.82) over 16 periods: at the end the periods still vary by ~5e-3, and the modulation is seen to decay:
  // settling.
  const CycleSettlingVerdict slow = settling_of(sample(24 * T, T / 50, modulated_pulses(T, 0.3, 4.3, 0.05 / T)));
  CHECK(slow.settling == CycleSettling::unsettled);
  CHECK(slow.contraction > 0.9);
  CHECK(slow.contraction < 1.0);
  const CycleSettlingVerdict faster = settling_of(sample(16 * T, T / 50, modulated_pulses(T, 0.3, 4.3, 0.2 / T)));
  CHECK(faster.settling == CycleSettling::settling);
  CHECK(faster.contraction < 0.9);
}

TEST_CASE("crossing periods: a missed crossing counts as two periods, a shrinking amplitude is not unsettled", "[unit][analysis]") {
  const double T = 889.0;
  // Every seventh pulse too low to cross the mid-range: one interval of 2T in each seven.
  const auto pulses = modulated_pulses(T, 0.1, 4.3);
  const auto missing = [&](double t) {
    const double x = pulses(t);
    return int(std::floor(t / T + 0.5)) % 7 == 3 ? 1.0 + 0.2 * (x - 1.0) / std::exp(4.0) : x;
  };
  const Series s = sample(30 * T, T / 50, missing);
  const CrossingPeriods c = crossing_periods(s.t, s.x);
  bool long_interval = false;
  for (double p : c.periods) long_interval = long_interval || p > 1.8 * T;
  REQUIRE(long_interval);
  const CycleSettlingVerdict v = cycle_settling(c, s.x);
  REQUIRE(v.settling == CycleSettling::unsettled);
  CHECK(std::abs(v.period - T) < 5e-3 * T);  // not (2T + 5T) / 6
  // The same modulation on an amplitude shrinking by 30 % over the run: settling.
  const Series shrinking = sample(24 * T, T / 50, [&](double t) { return (1.0 - 0.3 * t / (24 * T)) * pulses(t); });
  CHECK(settling_of(shrinking).settling == CycleSettling::settling);
}

TEST_CASE("crossing periods: too few crossings, and series of different lengths", "[unit][analysis]") {
  const double T = 10.0;
  CHECK(settling_of(sample(2.5 * T, T / 50, modulated_pulses(T, 0.0, 1.0))).settling == CycleSettling::too_few_crossings);
  // A modulation over only 8 periods: too short to call unsettled.
  CHECK(settling_of(sample(9 * T, T / 50, modulated_pulses(T, 0.1, 4.3))).settling == CycleSettling::settling);
  const std::vector<double> t = {0, 1, 2}, x = {0, 1};
  CHECK_THROWS_AS(crossing_periods(t, x), InputError);
  CHECK(to_string(CycleSettling::unsettled) == "unsettled");
}

TEST_CASE("crossing periods: at unequally spaced samples the peaks come from the parabola through them") {
  // A cycle of period 1 with sharp peaks e^8 (exp(8 cos 2π t)), sampled about 100 times a period at spacings that
  // vary by ±90 % (as a run's internal steps are): the parabola through the largest sample and its neighbours
  // at their own times puts every peak within 4e-5 of e^8, and the cycle settles. Read as equally spaced, the
  // same samples give peaks that differ by 5.2e-3 between the last two periods (1.00181 and 0.99659 of e^8),
  // beyond the 5e-3 that settling allows.
  Series s;
  double t = 0.0;
  for (int k = 1; t <= 12.0; ++k) {
    s.t.push_back(t);
    s.x.push_back(std::exp(8.0 * std::cos(two_pi * t)));
    t += 0.01 * (1.0 + 0.9 * std::sin(k * 2.399963));
  }
  const CrossingPeriods c = crossing_periods(s.t, s.x);
  const CycleSettlingVerdict timed = cycle_settling(c, s.t, s.x);
  CHECK(timed.settling == CycleSettling::settled);
  CHECK(timed.period == Approx(1.0).epsilon(1e-4));
  CHECK(cycle_settling(c, s.x).settling == CycleSettling::settling);
  CHECK_THROWS_AS(cycle_settling(c, std::span<const double>(s.t).first(3), s.x), InputError);
}

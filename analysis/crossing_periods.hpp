#pragma once
// The periods of a sustained oscillation read from the upward crossings of its mid-range, and whether they
// have settled on one cycle. The crossings, not the turning points, give the period of a relaxation cycle: far
// below the Hopf curve of the aggregation-shattering equations M0 has secondary maxima within each period
// (a = 0.9, λ = 1e-4 on a 34-class grid: peaks 0.097, 0.0062, 0.0032, 0.0025 in a period of 1335), which a
// turning-point classifier counts as cycles of their own.
//
// Three outcomes for a series that crosses its mid-range often enough:
// - unsettled (tested first, since a few periods of a modulated oscillation can agree by chance): the periods
//   keep varying and do not converge, a modulation that persists: over at least
//   `min_unsettled_periods` periods, split into an earlier and a later half, the spread (largest − smallest)
//   of the later half's periods is at least ρ^m of the earlier half's (m periods a half, ρ = 0.9 per period),
//   the spread is more than 2e-3 of the period, the halves' mean periods agree within half the spread, and
//   their largest values agree to 5 % (an interval of more than 1.5 median periods, where a low swing missed
//   the mid-range, counts as round(interval / median) periods). That is a quasi-periodic oscillation (an
//   invariant torus after a Neimark–Sacker bifurcation of the cycle [Kuznetsov2004, Ch. 4]), a period-k cycle,
//   or a cycle whose nontrivial Floquet multipliers have |μ| ≥ 0.9; either way a bounded oscillation that
//   neither grows nor decays, its mean period the mean of the halves' periods, and the per-period contraction
//   ρ of the modulation reported. Sampling alone can make such a modulation: a burst narrower than the output
//   spacing Δ is crossed at a sampling phase that drifts by frac(T/Δ) a period, so the interpolated crossings
//   wander with a beat of 1/frac(T/Δ) periods (a = 0.9, λ = 1.78e-4 at 50 outputs a period: T/Δ = 49.23, periods
//   1647 … 1666 recurring every 4.3 periods; at 400 outputs a period the same cycle settled);
// - settled: otherwise, where the last four periods agree to 2e-3 and M0's largest value over the last two to
//   5e-3 (its smallest, where the outputs do not resolve a peak: a neighbour of the largest sample below 95 %
//   of it) — one periodic orbit, its period the mean of the last four (near the turning points of a slow
//   modulation three consecutive periods can agree to 2e-3 by chance: tests/analysis/test_crossing_periods.cpp);
// - settling: neither yet (a run on may settle it).
#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace aggkit {

struct CrossingPeriods {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  double lowest = nan, highest = nan;   // the series' range; the crossings are of its middle
  std::vector<double> crossings;        // upward crossings of the middle, linearly interpolated
  std::vector<std::size_t> after;       // index of the first sample at or above the middle of each crossing
  std::vector<double> periods;          // successive differences of the crossings
};

// The upward crossings of 0.5 (min + max) of x(t). `t` increasing, both of the same length (else InputError).
CrossingPeriods crossing_periods(std::span<const double> t, std::span<const double> x);

enum class CycleSettling { too_few_crossings, settling, settled, unsettled };
std::string to_string(CycleSettling s);

struct CycleSettlingVerdict {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  CycleSettling settling = CycleSettling::too_few_crossings;
  double period = nan;       // settled: the mean of the last four periods; otherwise the mean of all
  double spread = nan;       // the last four periods' spread (settled, settling) or the later half's (unsettled), / period
  double contraction = nan;  // ρ, the per-period ratio of the later half's spread to the earlier half's (nan: too few)
  std::size_t periods = 0;   // periods between crossings
};

constexpr std::size_t min_unsettled_periods = 10;

// The largest x from sample `from` up to (not including) `to`: the vertex of the parabola through the largest
// sample and its neighbours (at the times t, or equally spaced where t is empty). A sampled maximum alone misses
// a peak by up to Δ²/8 of its curvature (Δ the spacing): a relaxation burst a few spacings wide (a = 0.85,
// λ = 3.16e-5, 400 outputs a period: neighbours at 0.88–1.0 of the largest sample) gave maxima differing by 1 %
// between periods that agree to 1.5e-4.
double peak_between(std::span<const double> t, std::span<const double> x, std::size_t from, std::size_t to);

// The crossings `c` of the series x, equally spaced in time.
CycleSettlingVerdict cycle_settling(const CrossingPeriods& c, std::span<const double> x);
// The same for samples at the times t (increasing; e.g. a run's internal steps), the
// peaks then from the parabola through unequally spaced samples. InputError where t and x differ in length.
CycleSettlingVerdict cycle_settling(const CrossingPeriods& c, std::span<const double> t, std::span<const double> x);

}  // namespace aggkit

#include "analysis/crossing_periods.hpp"

#include <algorithm>
#include <cmath>

#include "analysis/input_error.hpp"

namespace aggkit {

namespace {

constexpr double settled_spread = 2e-3;      // of the last four periods, relative to their mean
constexpr double settled_peak = 5e-3;        // M0's largest value over the last two periods, relative
constexpr double unsettled_contraction = 0.9;  // ρ per period at or above which a modulation persists
// The halves' largest values, relative: an oscillation whose amplitude still shrinks towards a smaller cycle is
// settling, not unsettled; a persisting modulation moves the largest value over ~5 periods by a few percent.
constexpr double unsettled_peak = 5e-2;

double spread_of(std::span<const double> p) {
  const auto [lo, hi] = std::minmax_element(p.begin(), p.end());
  return *hi - *lo;
}

double mean_of(std::span<const double> p) {
  double sum = 0.0;
  for (double v : p) sum += v;
  return sum / double(p.size());
}

// Whether the outputs resolve the largest value from `from` to `to`: both neighbours of the largest sample
// within 5 % of it. A narrower burst is sampled at a phase that drifts from period to period, and its sampled
// (or interpolated) height with it: a = 0.9, λ = 3.16e-5 at 400 outputs a period, periods agreeing to 4e-5,
// stopped its column on peaks that differed by more than 5e-3.
bool peak_resolved(std::span<const double> x, std::size_t from, std::size_t to) {
  const auto top = std::max_element(x.begin() + std::ptrdiff_t(from), x.begin() + std::ptrdiff_t(to));
  const std::size_t i = std::size_t(top - x.begin());
  return i > 0 && i + 1 < x.size() && std::min(x[i - 1], x[i + 1]) >= 0.95 * *top;
}

// The smallest value from `from` to `to` (the quiescent phase of a relaxation cycle, resolved by the outputs).
double trough(std::span<const double> x, std::size_t from, std::size_t to) {
  return *std::min_element(x.begin() + std::ptrdiff_t(from), x.begin() + std::ptrdiff_t(to));
}

double median_of(std::span<const double> p) {
  std::vector<double> sorted(p.begin(), p.end());
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() / 2), sorted.end());
  return sorted[sorted.size() / 2];
}

// The periods of `p` with each one of more than 1.5 times `median` split into round(p / median) equal parts:
// where the amplitude is modulated, a low swing can miss the mid-range and one interval then spans two periods
// (a = 0.95, λ = 3.16e-4 at 50 outputs a period: 1781.2 among periods of 874 … 906).
std::vector<double> whole_periods(std::span<const double> p, double median) {
  std::vector<double> whole;
  for (double v : p) {
    const double parts = v > 1.5 * median ? std::round(v / median) : 1.0;
    for (int k = 0; k < int(parts); ++k) whole.push_back(v / parts);
  }
  return whole;
}

}  // namespace

double peak_between(std::span<const double> t, std::span<const double> x, std::size_t from, std::size_t to) {
  const auto top = std::max_element(x.begin() + std::ptrdiff_t(from), x.begin() + std::ptrdiff_t(to));
  const std::size_t i = std::size_t(top - x.begin());
  if (i == 0 || i + 1 >= x.size()) return *top;
  // p(s) = x_i + B s + A s² through the three samples, s the time from sample i (in spacings where t is empty).
  const double h0 = t.empty() ? -1.0 : t[i - 1] - t[i], h2 = t.empty() ? 1.0 : t[i + 1] - t[i];
  const double y0 = x[i - 1] - x[i], y2 = x[i + 1] - x[i];
  if (!(h0 < 0.0 && h2 > 0.0)) return *top;
  const double A = (y0 * h2 - y2 * h0) / (h0 * h2 * (h0 - h2)), B = (y0 * h2 * h2 - y2 * h0 * h0) / (h0 * h2 * (h2 - h0));
  return A < 0.0 ? *top - B * B / (4.0 * A) : *top;
}

CrossingPeriods crossing_periods(std::span<const double> t, std::span<const double> x) {
  if (t.size() != x.size())
    throw InputError("series", std::to_string(t.size()) + " times and " + std::to_string(x.size()) + " values",
                     "as many values as times");
  CrossingPeriods c;
  if (x.empty()) return c;
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  c.lowest = *lo;
  c.highest = *hi;
  const double middle = 0.5 * (c.lowest + c.highest);
  for (std::size_t i = 1; i < x.size(); ++i)
    if (x[i - 1] < middle && x[i] >= middle) {
      c.crossings.push_back(t[i - 1] + (middle - x[i - 1]) * (t[i] - t[i - 1]) / (x[i] - x[i - 1]));
      c.after.push_back(i);
    }
  for (std::size_t i = 1; i < c.crossings.size(); ++i) c.periods.push_back(c.crossings[i] - c.crossings[i - 1]);
  return c;
}

std::string to_string(CycleSettling s) {
  switch (s) {
    case CycleSettling::too_few_crossings: return "too few crossings";
    case CycleSettling::settling: return "settling";
    case CycleSettling::settled: return "settled";
    case CycleSettling::unsettled: return "unsettled";
  }
  return "?";
}

// Whether the modulation of the last 2m periods persists (CycleSettling::unsettled, with the halves' mean
// period and the later half's spread), and the contraction ρ, into v; false where it decays or is within 2e-3.
bool persisting_modulation(const CrossingPeriods& c, std::span<const double> t, std::span<const double> x,
                           CycleSettlingVerdict& v) {
  const std::span<const double> p(c.periods);
  const std::size_t n = c.crossings.size();
  const std::size_t m = p.size() / 2;  // periods a half; the earlier half drops the first period if odd
  const double median = median_of(p);
  const std::vector<double> earlier = whole_periods(p.subspan(p.size() - 2 * m, m), median),
                            later = whole_periods(p.last(m), median);
  const double spread_earlier = spread_of(earlier), spread_later = spread_of(later);
  const double mean_later = mean_of(later);
  v.contraction = spread_earlier > 0.0 ? std::pow(spread_later / spread_earlier, 1.0 / double(later.size())) : std::nan("");
  const std::size_t half = n - 1 - m;  // crossing index where the later half begins
  const double peak_earlier = peak_between(t, x, c.after[n - 1 - 2 * m], c.after[half]);
  const double peak_later = peak_between(t, x, c.after[half], c.after[n - 1]);
  const bool persists = v.contraction >= unsettled_contraction && spread_later > settled_spread * mean_later &&
                        std::abs(mean_of(earlier) - mean_later) <= 0.5 * spread_later &&
                        std::abs(peak_earlier - peak_later) <= unsettled_peak * peak_later;
  if (!persists) return false;
  v.settling = CycleSettling::unsettled;
  v.period = (mean_of(earlier) * double(earlier.size()) + mean_later * double(later.size())) / double(earlier.size() + later.size());
  v.spread = spread_later / mean_later;
  return true;
}

CycleSettlingVerdict cycle_settling(const CrossingPeriods& c, std::span<const double> x) { return cycle_settling(c, {}, x); }

CycleSettlingVerdict cycle_settling(const CrossingPeriods& c, std::span<const double> t, std::span<const double> x) {
  if (!t.empty() && t.size() != x.size())
    throw InputError("series", std::to_string(t.size()) + " times and " + std::to_string(x.size()) + " values",
                     "as many values as times");
  CycleSettlingVerdict v;
  const std::size_t n = c.crossings.size();
  v.periods = c.periods.size();
  // A persisting modulation first: a few consecutive periods of a modulated oscillation can agree to 2e-3 by
  // chance.
  if (v.periods >= min_unsettled_periods && persisting_modulation(c, t, x, v)) return v;
  if (n < 5) return v;
  const std::span<const double> last4 = std::span<const double>(c.periods).last(4);
  v.period = mean_of(last4);
  v.spread = spread_of(last4) / v.period;
  // The amplitude has settled where the last two peaks agree; where a peak is narrower than the outputs resolve,
  // the last two troughs are compared instead.
  const std::size_t p0 = c.after[n - 3], p1 = c.after[n - 2], p2 = c.after[n - 1];
  const bool resolved = peak_resolved(x, p0, p1) && peak_resolved(x, p1, p2);
  const double last = resolved ? peak_between(t, x, p1, p2) : trough(x, p1, p2), before = resolved ? peak_between(t, x, p0, p1) : trough(x, p0, p1);
  v.settling = v.spread <= settled_spread && std::abs(last - before) <= settled_peak * std::abs(last) ? CycleSettling::settled
                                                                                                      : CycleSettling::settling;
  return v;
}

}  // namespace aggkit

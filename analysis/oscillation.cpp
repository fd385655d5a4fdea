#include "analysis/oscillation.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "analysis/input_error.hpp"
#include "analysis/least_squares.hpp"

namespace aggkit {

std::string to_string(Regime regime) {
  switch (regime) {
    case Regime::steady: return "steady";
    case Regime::damped: return "damped";
    case Regime::sustained: return "sustained";
    case Regime::irregular: return "irregular";
  }
  return "?";
}

void OscillationCriteria::validate() const {
  const auto check = [](const char* key, double value, bool ok, const char* allowed) {
    if (!ok) throw InputError(std::string("oscillation.") + key, format_value(value), allowed);
  };
  check("tail_fraction", tail_fraction, tail_fraction > 0 && tail_fraction <= 1, "a fraction in (0, 1]");
  check("steady_tolerance", steady_tolerance, steady_tolerance > 0 && steady_tolerance < 1, "in (0, 1)");
  check("drift_tolerance", drift_tolerance, drift_tolerance > 0 && drift_tolerance < 1, "in (0, 1)");
  check("period_tolerance", period_tolerance, period_tolerance > 0 && period_tolerance < 1, "in (0, 1)");
  check("regularity_tolerance", regularity_tolerance, regularity_tolerance > 0 && regularity_tolerance < 1,
        "in (0, 1)");
  check("prominence", prominence, prominence > 0 && prominence < 1, "in (0, 1)");
  check("minimum_cycles", double(minimum_cycles), minimum_cycles >= 2, "an integer >= 2");
}

namespace {

struct TurningPoint {
  double t, x;
  bool maximum;
};

// The vertex of the parabola through (i-1, i, i+1): position and value of a sampled extremum to O(Δt^4)
// for a smooth signal (the discrete maximum alone is off by O(Δt^2)).
TurningPoint refine(std::span<const double> t, std::span<const double> x, std::size_t i, bool maximum) {
  TurningPoint p{t[i], x[i], maximum};
  if (i == 0 || i + 1 >= x.size()) return p;
  const double left = x[i - 1], mid = x[i], right = x[i + 1];
  const double curvature = left - 2 * mid + right;
  if (curvature == 0) return p;
  const double offset = 0.5 * (left - right) / curvature;  // in samples, |offset| <= 1/2 at a discrete extremum
  if (std::abs(offset) > 1) return p;
  const double dt = t[i + 1] - t[i];
  p.t = t[i] + offset * dt;
  p.x = mid - 0.25 * (left - right) * offset;
  return p;
}

// Turning points confirmed by a reversal of at least `reversal` (hysteresis: noise smaller than that makes
// none). Extrema on the first or last sample are not turning points (the signal may continue beyond).
std::vector<TurningPoint> turning_points(std::span<const double> t, std::span<const double> x, double reversal) {
  std::vector<TurningPoint> points;
  std::size_t high = 0, low = 0;  // candidate maximum / minimum since the last confirmed turning point
  int direction = 0;               // +1 looking for a maximum, -1 for a minimum, 0 not yet known
  for (std::size_t i = 1; i < x.size(); ++i) {
    if (direction >= 0 && x[i] > x[high]) high = i;
    if (direction <= 0 && x[i] < x[low]) low = i;
    if (direction >= 0 && x[i] < x[high] - reversal) {
      if (high > 0) points.push_back(refine(t, x, high, true));
      direction = -1;
      low = i;
    } else if (direction <= 0 && x[i] > x[low] + reversal) {
      if (low > 0) points.push_back(refine(t, x, low, false));
      direction = +1;
      high = i;
    }
  }
  return points;  // the last candidate is unconfirmed and left out
}

double mean_of(std::span<const double> v) { return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size()); }

void check_series(std::span<const double> t, std::span<const double> x) {
  if (t.size() != x.size())
    throw InputError("series", std::to_string(x.size()) + " values",
                     "as many values as times (" + std::to_string(t.size()) + ")");
  if (t.size() < 3) throw InputError("series", std::to_string(t.size()) + " samples", "at least 3 samples");
  const double dt = (t.back() - t.front()) / double(t.size() - 1);
  if (!(dt > 0)) throw InputError("series.t", format_value(t.back()), "increasing times");
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (!std::isfinite(x[i]))
      throw InputError("series.x[" + std::to_string(i) + "]", format_value(x[i]), "a finite value");
    if (i > 0 && std::abs(t[i] - t[i - 1] - dt) > 1e-6 * dt)
      throw InputError("series.t[" + std::to_string(i) + "]", format_value(t[i]),
                       "uniformly spaced times (spacing " + format_value(dt) + ")");
  }
}

// No complete cycle: a monotone relaxation x∞ + c e^{-γt} (or a drift). Its increments decay at rate γ.
void classify_monotone(std::span<const double> t, std::span<const double> x, const OscillationCriteria& criteria,
                       OscillationClassification& c) {
  std::vector<double> times, logs;
  for (std::size_t i = 1; i < x.size(); ++i) {
    const double dx = std::abs(x[i] - x[i - 1]);
    if (dx > 0) {
      times.push_back(0.5 * (t[i] + t[i - 1]));
      logs.push_back(std::log(dx));
    }
  }
  // Unweighted: ln|Δx| has about the same scatter at every time (relative noise of the increments),
  // so ordinary least squares is the estimator, and its slope error the standard error of γ.
  const LineFit fit = fit_line(times, logs);
  c.decay_rate = -fit.slope;  // NaN if fewer than two increments are non-zero
  c.decay_rate_error = fit.slope_error;
  // Either way it does not oscillate: damped (no persistent oscillation), converged only for a clean
  // exponential relaxation.
  c.regime = Regime::damped;
  c.converged = c.decay_rate * (t.back() - t.front()) > criteria.drift_tolerance;
  c.note = c.converged ? "monotone relaxation" : "monotone drift, not yet relaxing exponentially: run longer";
}

// Cycle amplitudes (half differences of successive turning points) at the midpoint times, and periods
// (spacing of turning points of the same kind).
struct Cycles {
  std::vector<double> amplitude_times, amplitudes, log_amplitudes, periods;
  explicit Cycles(const std::vector<TurningPoint>& points) {
    for (std::size_t j = 0; j + 1 < points.size(); ++j) {
      amplitude_times.push_back(0.5 * (points[j].t + points[j + 1].t));
      amplitudes.push_back(0.5 * std::abs(points[j + 1].x - points[j].x));
      log_amplitudes.push_back(std::log(std::max(amplitudes.back(), 1e-300)));
    }
    for (std::size_t j = 0; j + 2 < points.size(); ++j) periods.push_back(points[j + 2].t - points[j].t);
  }
  // The relative standard deviation of the periods.
  double period_scatter() const {
    const double period_mean = mean_of(periods);
    double variance = 0;
    for (double p : periods) variance += (p - period_mean) * (p - period_mean);
    return periods.size() > 1 ? std::sqrt(variance / double(periods.size() - 1)) / period_mean : 0;
  }
};

// |second half's mean − first half's| over the second's (0 with fewer than 4 values).
double change_between_halves(const std::vector<double>& values) {
  if (values.size() < 4) return 0;
  const std::size_t half = values.size() / 2;
  const double first = mean_of(std::span<const double>(values).first(half));
  const double second = mean_of(std::span<const double>(values).last(half));
  return std::abs(second - first) / second;
}

// The amplitude from the RMS of x over whole cycles (from the first turning point to the last of its kind):
// √2 times the standard deviation, exact for a sine.
double rms_amplitude(std::span<const double> t, std::span<const double> x, const std::vector<TurningPoint>& points) {
  const std::size_t last_same = points.size() - 1 - (points.size() - 1) % 2;  // same kind as points[0]
  double sum = 0, squares = 0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] >= points.front().t && t[i] < points[last_same].t) sum += x[i], squares += x[i] * x[i], ++count;
  const double m = sum / double(count);
  return std::sqrt(2.0 * std::max(0.0, squares / double(count) - m * m));
}

// The regime from the scatter of the periods and the change of the envelope over the fitted span.
void judge(double period_scatter, double envelope_change, const OscillationCriteria& criteria,
           OscillationClassification& c) {
  if (period_scatter > criteria.regularity_tolerance) {
    c.regime = Regime::irregular;
    c.note = "cycle lengths scatter by " + std::to_string(int(std::round(100 * period_scatter))) +
             " %: noise or chaos, not a periodic or linearly damped mode";
    return;
  }
  const bool enough_cycles = c.cycles >= criteria.minimum_cycles;
  if (envelope_change > criteria.drift_tolerance) {
    c.regime = Regime::damped;
    c.converged = enough_cycles;
  } else if (envelope_change < -criteria.drift_tolerance) {
    c.regime = Regime::sustained;
    c.converged = false;
    c.note = "amplitude still growing (unstable steady state; limit cycle not reached): run longer";
  } else {
    c.regime = Regime::sustained;
    c.converged = enough_cycles && c.amplitude_change <= criteria.drift_tolerance &&
                  c.period_change <= criteria.period_tolerance;
    if (!c.converged && enough_cycles) c.note = "amplitude or period not converged between the halves of the tail";
  }
  if (!enough_cycles)
    c.note = "only " + std::to_string(c.cycles) + " cycles in the tail (" + std::to_string(criteria.minimum_cycles) +
             " needed for a converged verdict): run longer";
}

}  // namespace

OscillationClassification classify_oscillation(std::span<const double> t_all, std::span<const double> x_all,
                                               const OscillationCriteria& criteria) {
  criteria.validate();
  check_series(t_all, x_all);
  const double t_start = t_all.back() - criteria.tail_fraction * (t_all.back() - t_all.front());
  const std::size_t first = std::size_t(std::lower_bound(t_all.begin(), t_all.end(), t_start - 1e-9) - t_all.begin());
  const std::span<const double> t = t_all.subspan(first), x = x_all.subspan(first);
  if (t.size() < 16)
    throw InputError("series", std::to_string(t.size()) + " samples in the tail",
                     "at least 16 samples in the classified tail (sample more often or raise tail_fraction)");

  OscillationClassification c;
  c.mean = mean_of(x);
  const auto [low, high] = std::minmax_element(x.begin(), x.end());
  const double half_swing = 0.5 * (*high - *low);
  const double scale = std::max(std::abs(c.mean), half_swing);
  c.amplitude = half_swing;
  c.relative_amplitude = c.mean != 0 ? half_swing / std::abs(c.mean) : OscillationClassification::nan;
  if (half_swing <= criteria.steady_tolerance * scale) {
    c.regime = Regime::steady;
    c.converged = true;
    return c;
  }

  const std::vector<TurningPoint> points = turning_points(t, x, criteria.prominence * half_swing);
  if (points.size() < 3) {
    classify_monotone(t, x, criteria, c);
    return c;
  }
  const Cycles cycles(points);
  c.cycles = cycles.periods.size() / 2;
  // The last cycles: amplitude and period reported; the first and second halves compared.
  const std::size_t last = std::min<std::size_t>(cycles.amplitudes.size(), 4);
  c.amplitude = mean_of(std::span<const double>(cycles.amplitudes).last(last));
  c.relative_amplitude = c.mean != 0 ? c.amplitude / std::abs(c.mean) : OscillationClassification::nan;
  c.period = mean_of(std::span<const double>(cycles.periods).last(std::min<std::size_t>(cycles.periods.size(), 4)));
  c.mean_period = mean_of(cycles.periods);
  c.mean_amplitude = mean_of(cycles.amplitudes);
  c.rms_amplitude = rms_amplitude(t, x, points);
  if (cycles.amplitudes.size() >= 4) c.amplitude_change = change_between_halves(cycles.amplitudes);
  if (cycles.periods.size() >= 4) c.period_change = change_between_halves(cycles.periods);

  // ln A_j against time, unweighted: the cycle amplitudes carry about the same relative error, i.e. the
  // same absolute error in ln A, whatever their size (a nonlinear fit of A0 e^{-γt} to A_j would instead
  // weight the large early cycles more and needs a start; the log-linear fit is exact for an exponential
  // envelope).
  const LineFit fit = fit_line(cycles.amplitude_times, cycles.log_amplitudes);
  c.decay_rate = -fit.slope;
  c.decay_rate_error = fit.slope_error;
  const double fitted_span = cycles.amplitude_times.back() - cycles.amplitude_times.front();
  judge(cycles.period_scatter(), c.decay_rate * fitted_span, criteria, c);
  return c;
}

}  // namespace aggkit

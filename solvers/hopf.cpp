// locate_hopf (declared in solvers/stability.hpp): λ_crit(a) of the brownian kernel (i/j)^a + (j/i)^a,
// where the rightmost complex pair of the Jacobian at the steady state crosses Re μ = 0.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "analysis/input_error.hpp"
#include "solvers/stability.hpp"

namespace aggkit {

namespace {

struct Sample {
  double x = 0;          // ln λ
  double growth = 0;     // Re μ of the rightmost complex pair (rightmost eigenvalue if none is complex)
  double omega = 0;      // Im μ of that pair (0 if none)
  std::vector<double> n; // the steady state
};

class GrowthRate {
 public:
  GrowthRate(const AggregationModel& base, double a, const HopfOptions& options) : base_(base), options_(options) {
    base_.kernel = Kernel::brownian(a);  // throws InputError for a outside [0, 1]
  }

  Sample at(double x, HopfPoint& point) {
    AggregationModel model = base_;
    model.lambda = ShatteringRate::constant(std::exp(x));
    // Continuation: start from the steady state at the nearest λ already solved.
    const Sample* nearest = nullptr;
    for (const Sample& s : samples_)
      if (!nearest || std::abs(s.x - x) < std::abs(nearest->x - x)) nearest = &s;
    SteadyStateResult steady;
    if (nearest) steady = solve_steady_state(model, options_.steady, nearest->n);
    if (!steady.converged) steady = solve_steady_state(model, options_.steady);
    ++point.evaluations;
    if (!steady.converged)
      throw std::runtime_error("locate_hopf: no steady state at a = " + format_value(point.a) +
                               ", lambda = " + format_value(std::exp(x)) + ": " + steady.note);
    const StabilityResult spectrum = analyse_stability(model, steady.n, 6, options_.stability);
    Sample s;
    s.x = x;
    s.n = std::move(steady.n);
    const std::complex<double> pair = rightmost_complex_pair(spectrum.rightmost);
    if (std::isnan(pair.real())) {
      s.growth = spectrum.rightmost.front().real();
    } else {
      s.growth = pair.real();
      s.omega = pair.imag();
    }
    if (!spectrum.rightmost.empty() && spectrum.rightmost.front().imag() == 0.0 && spectrum.rightmost.front().real() > 0.0)
      point.note += "a real eigenvalue is positive at lambda = " + format_value(std::exp(x)) + "; ";
    samples_.push_back(s);
    return samples_.back();
  }

 private:
  AggregationModel base_;
  HopfOptions options_;
  std::vector<Sample> samples_;
};

}  // namespace

HopfPoint locate_hopf(const AggregationModel& base, double a, double lambda_lo, double lambda_hi,
                      double relative_tolerance) {
  return locate_hopf(base, a, lambda_lo, lambda_hi, relative_tolerance, HopfOptions{});
}

HopfPoint locate_hopf(const AggregationModel& base, double a, double lambda_lo, double lambda_hi,
                      double relative_tolerance, const HopfOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  if (!(lambda_lo > 0.0) || !std::isfinite(lambda_lo))
    throw InputError("lambda_lo", format_value(lambda_lo), "a finite shattering rate > 0");
  if (!(lambda_hi > lambda_lo) || !std::isfinite(lambda_hi))
    throw InputError("lambda_hi", format_value(lambda_hi), "a finite shattering rate > lambda_lo");
  if (!(relative_tolerance > 0.0 && relative_tolerance < 1.0))
    throw InputError("relative_tolerance", format_value(relative_tolerance), "a number in (0, 1)");
  HopfPoint point;
  point.a = a;
  GrowthRate growth(base, a, options);
  // Stable end first: its steady state is the easiest start (CVODE relaxes to it).
  auto finish = [&] {
    point.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return point;
  };
  Sample upper = growth.at(std::log(lambda_hi), point);
  Sample lower;
  try {
    lower = growth.at(std::log(lambda_lo), point);
  } catch (const std::runtime_error& e) {
    // Small λ with a short truncation: the quasi-steady state may have no positive root (a larger N is
    // needed); the bracket cannot be closed, which is a result, not a failure of the search.
    point.note += std::string("no steady state at lambda_lo (raise lambda_lo or N): ") + e.what();
    return finish();
  }
  if (upper.growth >= 0.0) {
    point.note += "unstable at lambda_hi = " + format_value(lambda_hi) + ": lambda_crit > lambda_hi";
    return finish();
  }
  if (lower.growth < 0.0) {
    point.note += "stable at lambda_lo = " + format_value(lambda_lo) + ": lambda_crit < lambda_lo (or no Hopf point)";
    return finish();
  }
  // Illinois regula falsi on g(ln λ): lower has g ≥ 0, upper g < 0. The bracket always holds the
  // crossing; it is narrowed until λ_upper / λ_lower ≤ 1 + relative_tolerance.
  double g_lower = lower.growth, g_upper = upper.growth;
  int side = 0;
  const double width = std::log1p(relative_tolerance);
  for (int iteration = 0; upper.x - lower.x > width && iteration < 60; ++iteration) {
    double x = (lower.x * g_upper - upper.x * g_lower) / (g_upper - g_lower);
    // Keep the trial point strictly inside (and not glued to an end that has stopped moving).
    const double margin = 0.05 * (upper.x - lower.x);
    x = std::clamp(x, lower.x + std::min(margin, 0.5 * width), upper.x - std::min(margin, 0.5 * width));
    Sample s = growth.at(x, point);
    if (s.growth >= 0.0) {
      lower = s;
      g_lower = s.growth;
      if (side == +1) g_upper *= 0.5;
      side = +1;
    } else {
      upper = s;
      g_upper = s.growth;
      if (side == -1) g_lower *= 0.5;
      side = -1;
    }
  }
  // The crossing from the final bracket's true growth rates (linear in ln λ); the bound is the bracket.
  const double t = lower.growth / (lower.growth - upper.growth);
  point.found = true;
  point.lambda_crit = std::exp(lower.x + t * (upper.x - lower.x));
  point.lambda_tolerance = std::exp(upper.x) - std::exp(lower.x);
  point.omega = lower.omega + t * (upper.omega - lower.omega);
  if (upper.x - lower.x > width) point.note += "bracket not narrowed to the tolerance in 60 steps; ";
  return finish();
}

}  // namespace aggkit

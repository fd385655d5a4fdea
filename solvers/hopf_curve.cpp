// locate_hopf_converged and hopf_curve (solvers/hopf_curve.hpp): λ_crit(a) converged in the truncation
// N by doubling it, and the curve by continuation in a.
#include "solvers/hopf_curve.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <stdexcept>

#include "analysis/input_error.hpp"

namespace aggkit {

void HopfCurveOptions::validate() const {
  auto in_range = [](const char* key, double v, double lo, double hi, const char* allowed) {
    if (!(v > lo && v < hi)) throw InputError(key, format_value(v), allowed);
  };
  in_range("relative_tolerance", relative_tolerance, 0.0, 0.1, "a number in (0, 0.1)");
  in_range("convergence", convergence, 0.0, 1.0, "a number in (0, 1)");
  in_range("bracket", bracket, 0.0, 10.0, "a number in (0, 10)");
  if (bracket_steps < 0) throw InputError("bracket_steps", std::to_string(bracket_steps), "an integer >= 0");
  if (min_size < 8) throw InputError("min_size", std::to_string(min_size), "an integer >= 8");
  if (max_size != 0 && max_size < 2 * min_size)
    throw InputError("max_size", std::to_string(max_size),
                     "0 (automatic) or an integer >= 2 min_size = " + std::to_string(2 * min_size));
  if (!(size_per_inverse_lambda >= 0.0) || !std::isfinite(size_per_inverse_lambda))
    throw InputError("size_per_inverse_lambda", format_value(size_per_inverse_lambda), "a finite number >= 0");
  if (!std::isfinite(log_slope)) throw InputError("log_slope", format_value(log_slope), "a finite number");
}

namespace {

std::size_t power_of_two_at_least(double x) {
  std::size_t n = 1;
  while (double(n) < x && n < (std::size_t(1) << 62)) n *= 2;
  return n;
}

bool no_steady_state(const HopfPoint& p) { return p.note.find("no steady state") != std::string::npos; }

// The graded grid's two refinements at the final N: the resolved block doubled and r - 1 halved, each
// searched in a bracket of ± convergence around λ_crit (stepped outwards if the crossing moved further)
// from the final steady state carried onto the finer grid.
void refine_grid(const AggregationModel& base, double a, const HopfCurveOptions& options, HopfOptions hopf,
                 ConvergedHopfPoint& result) {
  const HopfPoint& final = result.by_size.back();
  hopf.start = final.steady_state;
  hopf.start_sizes = final.steady_sizes;
  hopf.start_a = a;
  hopf.start_lambda = final.steady_lambda;
  result.resolved = base.grid.resolved;
  result.ratio = base.grid.ratio;
  result.unknowns = final.steady_state.size();
  const bool converged_in_N = result.converged;
  auto refined = [&](SizeGrid grid, const char* what, double& lambda, double& change) {
    AggregationModel model = base;
    model.size = result.size;
    if (model.initial.size() > model.size) model.initial.resize(model.size);
    model.grid = grid;
    const double lo = result.lambda_crit / (1.0 + options.convergence), hi = result.lambda_crit * (1.0 + options.convergence);
    HopfPoint p;
    try {
      p = locate_hopf(model, a, lo, hi, options.relative_tolerance, hopf);
    } catch (const std::runtime_error& e) {
      p.note = e.what();
    }
    result.by_size.push_back(p);
    result.sizes.push_back(model.size);
    result.evaluations += p.evaluations;
    if (!p.found) {
      result.converged = false;
      result.note += std::string(what) + " (" + grid.describe() + "): " + p.note + "; ";
      return;
    }
    lambda = p.lambda_crit;
    change = std::abs(p.lambda_crit - result.lambda_crit) / result.lambda_crit;
    if (change > options.convergence) {
      result.converged = false;
      result.note += std::string(what) + " moves lambda_crit by " + format_value(change) + " (> convergence " +
                     format_value(options.convergence) + "); ";
    }
  };
  SizeGrid twice = base.grid;
  twice.resolved *= 2;
  refined(twice, "K doubled", result.lambda_crit_2K, result.change_K);
  refined(base.grid.refined(), "r - 1 halved", result.lambda_crit_fine_ratio, result.change_ratio);
  result.converged = result.converged && converged_in_N;
}

}  // namespace

ConvergedHopfPoint locate_hopf_converged(const AggregationModel& base, double a, double lambda_guess, std::size_t size,
                                         const HopfCurveOptions& options, std::span<const double> start,
                                         std::span<const double> start_sizes, double start_a, double start_lambda) {
  options.validate();
  if (!(lambda_guess > 0.0) || !std::isfinite(lambda_guess))
    throw InputError("lambda_guess", format_value(lambda_guess), "a finite shattering rate > 0");
  const auto started = std::chrono::steady_clock::now();
  const std::clock_t cpu_started = std::clock();
  ConvergedHopfPoint result;
  result.a = a;
  // The first N: the caller's, at least min_size and size_per_inverse_lambda / λ (a tail of ~10 decay
  // lengths), at most max_size / 2 so that one doubling remains possible.
  std::size_t N = power_of_two_at_least(std::max({double(size), double(options.min_size),
                                                   options.size_per_inverse_lambda / lambda_guess}));
  const std::size_t max_size = options.effective_max_size(base.grid);
  N = std::min(N, max_size / 2);
  HopfOptions hopf = options.hopf;
  hopf.bracket_steps = options.bracket_steps;
  hopf.start.assign(start.begin(), start.end());
  hopf.start_sizes.assign(start_sizes.begin(), start_sizes.end());
  hopf.start_a = start_a;
  hopf.start_lambda = start.empty() ? 0.0 : start_lambda;
  double guess = lambda_guess, half_width = options.bracket;
  std::size_t previous = 0;  // 1 + index in by_size of the last λ_crit found at N / 2 (0: none)
  std::size_t retried_at = 0;  // the N last searched again with a ±50 % bracket
  std::vector<double> last_sizes;  // pivots of the N that found the last λ_crit (graded grid)
  for (; N <= max_size; N *= 2) {
    AggregationModel model = base;
    model.size = N;
    if (model.initial.size() > N) model.initial.resize(N);  // entries beyond N must be zero (validate() says so)
    const double lo = guess / (1.0 + half_width), hi = guess * (1.0 + half_width);
    try {
      result.by_size.push_back(locate_hopf(model, a, lo, hi, options.relative_tolerance, hopf));
    } catch (const std::runtime_error& e) {
      // A failed steady state at either end (not only at lambda_lo): this N is too short as well.
      HopfPoint failed;
      failed.a = a;
      failed.note = std::string("no steady state: ") + e.what();
      result.by_size.push_back(failed);
    }
    result.sizes.push_back(N);
    // A guess off by more than the stepped bracket reaches (λ_crit falls by orders of magnitude per 0.05 in
    // a below a = 0.7, and a λ_crit found at an N still too short for it moves by more than the ±convergence
    // bracket of the next N): once per N, the same N again with a bracket of ±50 %, whose steps then span e^±12.
    if (!result.by_size.back().found && retried_at != N && half_width < 0.5 &&
        (result.by_size.back().note.find("stable at lambda_lo") != std::string::npos ||
         result.by_size.back().note.find("unstable at lambda_hi") != std::string::npos ||
         result.by_size.back().note.find("no steady state at lambda_hi") != std::string::npos)) {
      result.evaluations += result.by_size.back().evaluations;
      result.note += "N = " + std::to_string(N) + ": " + result.by_size.back().note + "; retried with a +-50 % bracket; ";
      half_width = 0.5;
      retried_at = N;
      N /= 2;  // the loop doubles it back
      continue;
    }
    const HopfPoint& p = result.by_size.back();
    result.evaluations += p.evaluations;
    if (!p.found) {
      // No positive quasi-steady state near λ at this N: the truncation is too short; double it.
      if (no_steady_state(p)) {
        previous = 0;
        // The search ran below the guess to where this N has no positive root: the next N is long enough for
        // that λ (4 size_per_inverse_lambda / λ: on the graded grid the roots go negative below λ ≈ 25 / N at
        // a = 0.6, r = 1.02), and its bracket starts where this one was last stable.
        if (p.lambda_lowest_steady > 0.0) {
          guess = p.lambda_lowest_steady;
          result.note += "N = " + std::to_string(N) + ": stable down to lambda = " + format_value(p.lambda_lowest_steady) +
                         ", no positive steady state at " + format_value(p.lambda_no_steady) + "; ";
        }
        if (p.lambda_no_steady > 0.0) {
          const std::size_t needed = power_of_two_at_least(4 * options.size_per_inverse_lambda / p.lambda_no_steady);
          // (at most max_size / 2, so that N / 2 -> N can still be compared)
          if (needed > 2 * N && max_size >= 4 * N) N = std::min(needed, max_size / 2) / 2;  // the loop doubles it
        }
        continue;
      }
      result.note += "N = " + std::to_string(N) + ": " + p.note + "; ";
      break;
    }
    result.lambda_crit = p.lambda_crit;
    result.omega = p.omega;
    result.size = N;
    result.bracket = p.lambda_tolerance;
    if (previous) {
      const double half = result.by_size[previous - 1].lambda_crit;
      result.lambda_crit_half = half;
      result.change = std::abs(p.lambda_crit - half) / p.lambda_crit;
      if (result.change <= options.convergence) {
        result.converged = true;
        break;
      }
    }
    previous = result.by_size.size();
    // The next N starts from this one: its λ_crit ± the convergence tolerance (a crossing inside shows the
    // change is within it) and its steady state.
    guess = p.lambda_crit;
    half_width = options.convergence;
    hopf.start = p.steady_state;
    hopf.start_sizes = p.steady_sizes;
    hopf.start_a = a;
    hopf.start_lambda = p.steady_lambda;
  }
  if (!result.converged) {
    if (result.size == 0)
      result.note += "no lambda_crit found up to N = " + std::to_string(max_size) + "; ";
    else
      result.note += "not converged in N up to " + std::to_string(std::min(N, max_size)) + "; ";
  }
  if (!base.grid.uniform() && result.size > 0) refine_grid(base, a, options, hopf, result);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  result.cpu_seconds = double(std::clock() - cpu_started) / CLOCKS_PER_SEC;
  return result;
}

std::vector<ConvergedHopfPoint> hopf_curve(const AggregationModel& base, std::span<const double> a_values,
                                           double lambda_guess, std::size_t size, const HopfCurveOptions& options,
                                           const std::function<void(const ConvergedHopfPoint&)>& on_point) {
  options.validate();
  std::vector<ConvergedHopfPoint> curve;
  std::vector<const ConvergedHopfPoint*> converged;
  curve.reserve(a_values.size());  // no reallocation: the pointers stay valid
  for (double a : a_values) {
    double guess = lambda_guess;
    std::size_t N = size;
    std::vector<double> start, start_sizes;
    double start_a = 0, start_lambda = 0;
    if (!converged.empty()) {
      const ConvergedHopfPoint& last = *converged.back();
      guess = last.lambda_crit * std::exp(options.log_slope * (a - last.a));
      if (converged.size() >= 2) {
        // ln λ_crit linear in a through the last two converged points.
        const ConvergedHopfPoint& before = *converged[converged.size() - 2];
        if (last.a != before.a)
          guess = std::exp(std::log(last.lambda_crit) +
                           (a - last.a) * (std::log(last.lambda_crit) - std::log(before.lambda_crit)) / (last.a - before.a));
      }
      if (converged.size() >= 3) {
        // Where ln λ_crit steepens (brownian a → 0.6: slopes 45, 134, 670 per unit a) a line overshoots by
        // orders of magnitude; ln λ = A − B/(a − u) through the last three points follows the steepening
        // (at a = 0.59 from 0.7, 0.65, 0.6: 2e-9 against 7e-11, where the line gives 1.5e-8).
        const double a1 = converged[converged.size() - 3]->a, a2 = converged[converged.size() - 2]->a, a3 = last.a;
        const double L1 = std::log(converged[converged.size() - 3]->lambda_crit),
                     L2 = std::log(converged[converged.size() - 2]->lambda_crit), L3 = std::log(last.lambda_crit);
        const double R = (L2 - L3) / (L1 - L2);
        const double u = ((a2 - a3) * a1 - R * (a1 - a2) * a3) / ((a2 - a3) - R * (a1 - a2));
        const double B = (L1 - L2) * (a1 - u) * (a2 - u) / (a1 - a2);
        const bool same_side = (a1 - u) * (a3 - u) > 0 && (a - u) * (a3 - u) > 0;
        if (std::isfinite(u) && std::isfinite(B) && same_side && B * (a3 - u) > 0) {
          const double hyperbolic = std::exp(L3 - B * (1.0 / (a - u) - 1.0 / (a3 - u)));
          // No more than 1.5 times the line's drop from the last point: the fit's pole can sit just below a
          // (from 0.65, 0.6, 0.59 it puts λ_crit(0.58) at 3e-25, beyond any λ with a positive root).
          const double floor = last.lambda_crit * std::pow(guess / last.lambda_crit, 1.5);
          if (std::isfinite(hyperbolic) && hyperbolic > 0) guess = std::max(std::min(guess, hyperbolic), floor);
        }
      }
      // N from the guess alone (options.size_per_inverse_lambda / λ, the tail's decay length): scaling the
      // last pair's N instead would ratchet it up by the power-of-two rounding at every a.
      N = options.min_size;
      start = last.by_size.back().steady_state;
      start_sizes = last.by_size.back().steady_sizes;
      start_a = last.a;
      start_lambda = last.by_size.back().steady_lambda;
    }
    curve.push_back(locate_hopf_converged(base, a, guess, N, options, start, start_sizes, start_a, start_lambda));
    if (curve.back().converged) converged.push_back(&curve.back());
    if (on_point) on_point(curve.back());
  }
  return curve;
}

}  // namespace aggkit

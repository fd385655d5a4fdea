#include "solvers/cycle_return_map.hpp"

#include <chrono>
#include <random>

#include <gsl/gsl_fit.h>

#include "analysis/input_error.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/discretisation.hpp"
#include "solvers/poincare_section.hpp"

namespace aggkit {

void ReturnMapOptions::validate() const {
  if (!(perturbation > 0.0 && perturbation <= 0.1))
    throw InputError("perturbation", format_value(perturbation), "a relative size in (0, 0.1]");
  if (max_returns < 3 || max_returns > 50) throw InputError("max_returns", std::to_string(max_returns), "an integer in [3, 50]");
  if (!(rtol > 0.0 && rtol < 1.0)) throw InputError("rtol", format_value(rtol), "a relative tolerance in (0, 1)");
  if (max_steps < 0) throw InputError("max_steps", std::to_string(max_steps), "a step count >= 1, or 0 for the default");
  if (!(floor > 0.0 && floor < 1.0)) throw InputError("floor", format_value(floor), "a relative floor in (0, 1)");
  if (!(resolved_factor >= 1.0 && std::isfinite(resolved_factor)))
    throw InputError("resolved_factor", format_value(resolved_factor), "a finite factor >= 1");
}

namespace {

struct EnoughReturns {};  // thrown from the step callback once the deviations have reached the floor

// The returns' relative period deviations, run from `from` until one lies within the resolved floor (after the
// second) or max_returns have been run.
std::vector<double> period_deviations(const AggregationModel& model, const std::vector<double>& from,
                                      const CycleReference& reference, const ReturnMapOptions& options, double resolved) {
  const double level = 0.5 * (reference.m0_min + reference.m0_max);
  IntegratorOptions run = cycle_run_options(options.rtol, options.max_steps, options.tolerance);
  std::vector<double> crossings, deviations;
  UpwardCrossings section(level);
  run.on_step = [&](double t, std::span<const double> n) {
    if (!section.add(t, n)) return;
    crossings.push_back(section.time());
    const std::size_t c = crossings.size();
    if (c < 3) return;
    const double change = (crossings[c - 1] - crossings[c - 2]) - (crossings[c - 2] - crossings[c - 3]);
    deviations.push_back(std::abs(change) / reference.period);
    if ((deviations.size() >= 2 && deviations.back() <= resolved) || int(deviations.size()) >= options.max_returns)
      throw EnoughReturns{};
  };
  IntegratorRestart restart;
  restart.densities = from;
  const double end = (double(options.max_returns) + 3.0) * reference.period;
  try {
    integrate(model, std::vector<double>{end}, run, [](double, std::span<const double>, double) {}, &restart);
  } catch (const EnoughReturns&) {
  }
  return deviations;
}

}  // namespace

std::vector<double> mass_keeping_perturbation(std::span<const double> on_cycle, std::span<const double> sizes, double epsilon) {
  std::mt19937_64 random(20240531);
  std::uniform_real_distribution<double> xi(-1.0, 1.0);
  std::vector<double> delta(on_cycle.size());
  double mass = 0.0, weight = 0.0;
  for (std::size_t k = 0; k < delta.size(); ++k) {
    delta[k] = epsilon * on_cycle[k] * xi(random);
    mass += sizes[k] * delta[k];
    weight += sizes[k] * sizes[k] * on_cycle[k];
  }
  std::vector<double> moved(on_cycle.begin(), on_cycle.end());
  for (std::size_t k = 0; k < delta.size(); ++k)
    moved[k] = std::max(0.0, moved[k] + delta[k] - (weight > 0.0 ? mass / weight : 0.0) * sizes[k] * on_cycle[k]);
  return moved;
}

void estimate_multiplier(const std::vector<double>& d, double resolved, ReturnMapMultiplier& result) {
  constexpr std::size_t fitted = 4;
  result.multiplier = result.multiplier_error = ReturnMapMultiplier::nan;
  result.bounded = false;
  std::size_t count = 0;  // d_1 .. d_count above the floor
  while (count + 1 < d.size() && d[count + 1] > resolved) ++count;
  const bool fell = count + 1 < d.size();  // d_{count+1} was run and lies within the floor
  std::string fit_note;
  if (count >= 2) {
    // The last `fitted` of them: the earlier returns still carry the next multipliers' shares, which can cancel
    // the first's (a = 0.95, λ = 0.01, graded K = 32: d_1 = 1.1e-5, then 2.2e-5, 1.1e-5, 7.7e-6, 4.8e-6, ...).
    const std::size_t first = count > fitted ? count - fitted + 1 : 1, points = count - first + 1;
    // Each ln d weighted by its uncertainty's inverse square: the floor is the deviations' absolute scatter, so ln d
    // is uncertain by ~floor / d, and a return just above the floor does not pull the fit as far as one a hundred
    // times above it (a = 0.95, λ = 1e-3, graded K = 32: 5.3e-5, 4.9e-6 and 2.1e-7 against a scatter of ~5e-8 read
    // 0.063 unweighted, where Arnoldi's |μ_1| is 0.093).
    std::vector<double> j(points), ln(points), w(points);
    for (std::size_t i = 0; i < points; ++i) {
      j[i] = double(i);
      ln[i] = std::log(d[first + i]);
      w[i] = std::pow(d[first + i] / resolved, 2);
    }
    double c0 = 0, c1 = 0, cov00 = 0, cov01 = 0, cov11 = 0, chisq = 0;
    gsl_fit_wlinear(j.data(), 1, w.data(), 1, ln.data(), 1, points, &c0, &c1, &cov00, &cov01, &cov11, &chisq);
    const std::string returns = "returns " + std::to_string(first) + " to " + std::to_string(count) + " (of those above the floor " + format_value(resolved) + ")";
    if (std::exp(c1) < 1.0 || !fell) {
      result.multiplier = std::exp(c1);
      // From the scatter about the line: the weights' covariance scaled by χ² / (points - 2).
      if (points > 2) result.multiplier_error = result.multiplier * std::sqrt(cov11 * chisq / double(points - 2));
      result.note = "from the decay over " + returns;
      return;
    }
    // Deviations that rise on the way to the floor are its noise (a = 0.7, λ = 3.16e-9: 3.2e-7 then 7.6e-7 against a
    // floor of 3e-7, then 8.9e-8): the bound below instead.
    fit_note = " (the fit over " + returns + " rose: " + format_value(std::exp(c1)) + ")";
  }
  const double from = d.empty() ? 0.0 : d[count];
  if (fell && from > resolved) {
    result.multiplier = resolved / from;
    result.bounded = true;
    result.note = "bounded: the deviation fell from " + format_value(from) + " to within the floor " + format_value(resolved) +
                  " in one return" + fit_note;
  } else if (fell) {
    // Even the first return lies within the floor (a = 0.75, λ = 1e-3: 6.5e-4 against the step's own spread 7.8e-4).
    result.note = "no estimate: the perturbation moved the period by " + format_value(from) + ", within the floor " +
                  format_value(resolved);
  } else {
    result.note = "too few returns: " + std::to_string(d.size()) + " deviations, none yet within the floor";
  }
}

ReturnMapMultiplier return_map_multiplier(const AggregationModel& model, std::span<const double> on_cycle,
                                          const CycleReference& reference, const ReturnMapOptions& options) {
  options.validate();
  if (!(reference.period > 0.0) || !std::isfinite(reference.period))
    throw InputError("period", format_value(reference.period), "the cycle's period, finite and > 0");
  if (!(reference.m0_max > reference.m0_min))
    throw InputError("m0_max", format_value(reference.m0_max), "M0's largest value on the cycle, above its smallest");
  if (!(reference.spread >= 0.0)) throw InputError("spread", format_value(reference.spread), "a relative scatter >= 0");
  if (on_cycle.size() != model.unknowns())
    throw InputError("on_cycle", std::to_string(on_cycle.size()) + " entries",
                     "one density per size class (" + std::to_string(model.unknowns()) + ")");
  const auto started = std::chrono::steady_clock::now();
  ReturnMapMultiplier result;
  result.floor = std::max(options.floor, reference.spread);
  const double resolved = options.resolved_factor * result.floor;
  const std::vector<double> sizes = make_discretisation(model)->sizes();
  result.deviations = period_deviations(model, mass_keeping_perturbation(on_cycle, sizes, options.perturbation), reference, options, resolved);
  estimate_multiplier(result.deviations, resolved, result);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace aggkit

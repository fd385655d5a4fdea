#include "validation/scan/scan_point.hpp"

#include <chrono>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "validation/observables/observed_state.hpp"
#include "validation/io/text.hpp"

#include "solvers/mass_constrained_system.hpp"
#include "solvers/stability.hpp"
#include "solvers/steady_state.hpp"

namespace aggkit {

bool scan_stability_available() { return true; }

namespace {

// Linear stability of the point's steady state: an unstable steady state (Re μ > 0) means sustained
// oscillations; a stable one relaxes, through damped oscillations if the rightmost eigenvalue is complex.
void classify_by_stability(const AggregationModel& model, double series_order, ScanRecord& r) {
  const SteadyStateResult steady = solve_steady_state(model);
  if (!steady.converged) {
    r.note += std::string(r.note.empty() ? "" : "; ") + "steady state not converged (residual " +
              shortest_text(steady.relative_residual) + ")";
    return;
  }
  // A root whose mass piles up in the largest class is the truncation's, not the system's: at λN << 1 the
  // steady tail (n_k ∝ k^-a e^{-0.65 λ k}) lies beyond N, and under `drop` Newton then finds a state with all
  // the mass in class N draining at the leak rate (a = 0.95, λ = 1e-6, N = 2048: 99.9 % of the mass there).
  // A resolved tail (λN ≥ 8) puts ~1e-4 / N of the mass in that class.
  const std::vector<double> sizes = model.pivots();
  const double top = sizes.back() * steady.n.back() / total_mass(steady.n, sizes);
  if (top > 0.01) {
    r.note += std::string(r.note.empty() ? "" : "; ") + "the steady state piles up at the truncation (" +
              shortest_text(top) + " of the mass in the largest class): N too short for lambda";
    return;
  }
  r.mean_steady = 0;  // the classified moment Σ n_i x_i^p of the steady state
  for (std::size_t i = 0; i < sizes.size(); ++i) r.mean_steady += steady.n[i] * std::pow(sizes[i], series_order);
  const StabilityResult stability = analyse_stability(model, steady.n);
  if (stability.rightmost.empty()) return;
  const std::complex<double> mu = stability.rightmost.front();
  r.rightmost_real = mu.real();
  r.rightmost_imag = std::abs(mu.imag());
  r.regime_stability = !stability.stable ? "sustained" : mu.imag() != 0 ? "damped" : "steady";
  const bool known = r.regime == "sustained" || r.regime == "damped" || r.regime == "steady";
  if (known) r.agree = (r.regime == "sustained") == (r.regime_stability == "sustained") ? "yes" : "no";
}

}  // namespace

ScanRecord run_scan_point(const ScanPlan& plan, const ScanPoint& point, std::size_t size,
                          const std::function<void(double t)>& progress, bool judge_relaxation) {
  const auto started = std::chrono::steady_clock::now();
  Scene run;  // the point's scene: the scan scene's model with this (a, λ, N) and its time grid
  run.name = plan.scene.name;
  run.model = point_model(plan, point.a, point.lambda, size);
  run.time = plan.scene.time;

  std::vector<double> times, values;
  times.reserve(run.time.outputs.size());
  values.reserve(run.time.outputs.size());
  EngineObserver observer;
  observer.measure = [&](double, const ObservedState& state) {
    Measurement m;
    m.values = {state.moment(plan.series_order)};
    return m;
  };
  observer.record = [&](double t, std::vector<Measurement> m) {
    times.push_back(t);
    values.push_back(m.front().values.front());
  };
  observer.progress = progress;
  plan.engine->run(run, observer);

  const OscillationClassification c = classify_oscillation(times, values, plan.criteria);
  ScanRecord r;
  r.index = point.index;
  r.a = point.a;
  r.lambda = point.lambda;
  r.size = size;
  r.regime = to_string(c.regime);
  r.period = c.period;
  r.amplitude = c.amplitude;
  r.mean = c.mean;
  r.decay_rate = c.decay_rate;
  r.decay_rate_error = c.decay_rate_error;
  r.cycles = c.cycles;
  r.converged = c.converged;
  r.note = c.note;
  if (plan.stability) classify_by_stability(run.model, plan.series_order, r);
  // A relaxing verdict must be resolved by the run and the grid: the steady state that linear stability
  // finds unstable (Re μ > 0) cannot relax, so a damped or steady time series there means the run is too
  // short for the period (or the truncation too short for the tail); and a damped verdict whose own
  // convergence check failed (too few cycles, a slow drift) is no verdict either, nor is a relaxation with no
  // steady state to relax to (at λ far below 1/t_end the run sees the coarsening of pure aggregation, whose
  // M0 decays monotonically, while the steady state's tail lies beyond the grid); nor a relaxation whose tail
  // has not come near the steady state (the same coarsening where the steady state exists but is reached
  // only after a time ~1/λ: the run is too short to show how it gets there). Such points are "unresolved":
  // neither damped nor sustained.
  if (judge_relaxation && is_relaxing(r)) {
    std::string why;
    if (r.regime_stability == "sustained")
      why = "linear stability: unstable steady state (Re mu = " + shortest_text(r.rightmost_real) + ")";
    else if (r.regime == "damped" && !r.converged)
      why = "the decay did not converge in the run";
    else if (plan.stability && r.regime_stability.empty())
      why = "no steady state was found to confirm the relaxation (a coarsening transient relaxes too)";
    else if (std::isfinite(r.mean_steady) && !(std::abs(r.mean - r.mean_steady) <= plan.steady_match * r.mean_steady))
      why = "the run ends before reaching the steady state (" + plan.series + " tail mean " + shortest_text(r.mean) +
            ", steady " + shortest_text(r.mean_steady) + "): too short for the relaxation";
    if (!why.empty()) {
      r.note = "was " + r.regime + " in the run; " + why + (r.note.empty() ? "" : "; " + r.note);
      r.regime = "unresolved";
      r.agree = "";
    }
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return r;
}

}  // namespace aggkit

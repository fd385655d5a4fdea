#include "validation/scan/scan_point.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "validation/observables/observed_state.hpp"
#include "validation/io/text.hpp"

#include "solvers/cvode_integrator.hpp"
#include "solvers/hopf_normal_form.hpp"
#include "solvers/limit_cycle.hpp"
#include "solvers/mass_constrained_system.hpp"
#include "solvers/stability.hpp"
#include "solvers/steady_branch.hpp"
#include "solvers/steady_state.hpp"

namespace aggkit {

bool scan_stability_available() { return true; }

// The branches of one scan (scan_plan.hpp), keyed by a, N and the grid.
class SteadyBranches {
 public:
  SteadyBranch& of(const AggregationModel& model, double a, double anchor) {
    const std::string key = shortest_text(a) + " " + std::to_string(model.size) + " " + model.grid.describe();
    std::lock_guard<std::mutex> lock(mutex_);
    auto found = branches_.find(key);
    if (found == branches_.end()) found = branches_.emplace(key, std::make_unique<SteadyBranch>(model, anchor)).first;
    return *found->second;
  }

 private:
  std::mutex mutex_;
  std::map<std::string, std::unique_ptr<SteadyBranch>> branches_;
};

std::shared_ptr<SteadyBranches> make_steady_branches() { return std::make_shared<SteadyBranches>(); }

namespace {

void add_note(ScanRecord& r, const std::string& text) { r.note += (r.note.empty() ? "" : "; ") + text; }

// The point's steady state by continuation (solvers/steady_branch.hpp); records how it was reached, or where
// the walk stopped. Where the scan grid's roots go negative (the graded scheme's overshoot at the steep front,
// solvers/size_grid.hpp) the walk is repeated once on the refined grid ((r - 1)/2), and `model` becomes that
// grid's model: the spectrum and the cycle are then computed there. nullopt: none reached.
std::optional<SteadyStateResult> branch_steady_state(const ScanPlan& plan, AggregationModel& model, double a,
                                                     double lambda, ScanRecord& r) {
  // A fixed anchor, not the scan's largest λ: a point's result then does not depend on the other points
  // (a resumed scan with a changed λ list reuses it). At λ = 0.1 the relaxation takes ~10 time units and the
  // solver's own start converges for every a of the brownian kernel.
  constexpr double anchor = 0.1;
  std::shared_ptr<SteadyBranches> branches = plan.branches ? plan.branches : make_steady_branches();
  BranchSteadyState found = branches->of(model, a, anchor).at(lambda);
  std::string coarse;
  AggregationModel finer = model;
  finer.grid = model.grid.refined();  // the uniform grid is its own
  if (!found.steady.converged && found.negative_root && std::isfinite(found.stopped_lambda) &&
      finer.grid.describe() != model.grid.describe()) {
    coarse = "the grid " + model.grid.describe() + " has no positive root below lambda = " +
             shortest_text(found.stopped_lambda) + "; on the refined grid ";
    BranchSteadyState refined = branches->of(finer, a, anchor).at(lambda);
    coarse += finer.grid.describe() + ": ";
    if (refined.steady.converged) model = finer;
    found = std::move(refined);
  }
  if (found.steady.converged) {
    r.steady_how = coarse + found.how;
    return found.steady;
  }
  if (found.negative_root && std::isfinite(found.stopped_lambda)) {
    r.steady_how = coarse + "no positive steady state on this grid: the continuation from lambda = " + shortest_text(anchor) +
                   " stopped at lambda = " + shortest_text(found.stopped_lambda) + " (the next root has negative densities)";
    r.verdict = "no-positive-steady-state";
  } else {
    r.steady_how = coarse + (std::isfinite(found.stopped_lambda)
                                 ? "not reached: the continuation stopped at lambda = " + shortest_text(found.stopped_lambda)
                                 : "not reached: no steady state at the anchor lambda = " + shortest_text(anchor));
    r.verdict = "unresolved";
  }
  add_note(r, "steady state not reached (" + found.note + ")");
  return std::nullopt;
}

// The verdict from the spectrum and the periodic orbit, the time series confirming: a stable steady state is
// damped (a complex rightmost pair: a stable focus) or steady (a real one: a stable node); an unstable one is
// sustained where a stable cycle was found (or, failing that, the run oscillates without decay), else only
// "unstable" (no attracting cycle found).
std::string verdict_of(const ScanRecord& r, bool stable, bool complex_pair) {
  if (stable) return complex_pair ? "damped" : "steady";
  return r.cycle_stable == "yes" || r.regime == "sustained" ? "sustained" : "unstable";
}

// The cycle search's run, off the steady state: its second half classified (M0). Where no confirmation run is
// made it stands as the point's run, and a sustained, converged verdict there is the oscillating run of
// verdict_of: evidence of an attracting oscillation even where shooting does not converge.
struct SearchRun {
  OscillationClassification classification;
  double end = 0;
  double period = NAN;  // the mean spacing of its last crossings
};

std::optional<SearchRun> classify_search_run(const ScanPlan& plan, const CycleStart& start, double end) {
  if (plan.series_order != 0 || start.m0.size() < 16) return std::nullopt;  // the scan classifies another moment
  OscillationCriteria criteria = plan.criteria;
  criteria.tail_fraction = 1.0;  // the series is the run's second half already
  try {
    return SearchRun{classify_oscillation(start.times, start.m0, criteria), end, start.period};
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// Where the cycle search's run starts and how long it runs: off the steady state (1e-3 of the dimers' density
// moved over from the monomers, M1 unchanged: the cycle of the same mass) for the growth, or where that is beyond
// cycle_run, on the Hopf normal form's cycle. nullopt (and a note) where neither fits in cycle_run.
struct SearchStart {
  std::vector<double> from;
  double settle = 0;
};

std::optional<SearchStart> search_start(const ScanPlan& plan, const AggregationModel& model, std::span<const double> steady,
                                        double re, double period, ScanRecord& r) {
  double settle = std::max({plan.scene.time.end, 16.0 * period, 24.0 / re});
  std::vector<double> from(steady.begin(), steady.end());
  if (settle > plan.cycle_run) {
    // Near the curve (Re μ small) the growth takes too long: start on the cycle the Hopf normal form predicts
    // (n* + 2ρ Re q, solvers/hopf_normal_form.hpp), whose amplitude error decays by e^{-2 Re μ t}: ln(1e3)/(2 Re μ)
    // takes it down by 1e3, with 16 periods after it. Far from the curve the prediction is rougher; the run then
    // has to carry it onto the cycle, and its second half says whether it did.
    const double near = std::max({plan.scene.time.end, 16.0 * period + std::log(1e3) / (2.0 * re)});
    std::string why = "; from the Hopf normal form's cycle t = " + shortest_text(near);
    if (near <= plan.cycle_run) {
      try {
        const HopfNormalForm form = hopf_normal_form(model, steady);
        from = form.cycle_point(steady);
        settle = near;
      } catch (const std::exception& e) {
        why = std::string("; no start from the Hopf normal form: ") + e.what();
      }
    }
    if (settle > plan.cycle_run) {
      add_note(r, "no cycle sought: reaching it takes a run to t = " + shortest_text(settle) + " (16 periods 2 pi/Im mu, 24/Re mu), beyond cycle_run = " +
                      shortest_text(plan.cycle_run) + why);
      return std::nullopt;
    }
    add_note(r, "the cycle search starts on the Hopf normal form's cycle");
  } else if (from.size() >= 2) {
    const std::vector<double> sizes = model.pivots();
    const double moved = std::min(1e-3 * from[1], 0.25 * from[0] * sizes[0] / sizes[1]);
    from[1] += moved;
    from[0] -= moved * sizes[1] / sizes[0];
  }
  return SearchStart{std::move(from), settle};
}

// The attracting cycle around an unstable focus μ = re ± i im (solvers/limit_cycle.hpp): started from a run of
// the point's model whose length comes from the spectrum, at least 16 linear periods 2π/im (8 in the half whose
// crossings are used) and 24 e-folding times 1/re (the scene's t_end at least), with outputs 50 per period;
// then shooting and the Floquet multipliers. The run starts at the steady state with 1e-3 of the dimers'
// density moved over from the monomers (M1 unchanged: the cycle of the same mass), so that the growth, not
// the relaxation from the initial state (~1/λ), sets its length: ~9/re to grow from that perturbation, and
// the rest to approach the cycle at the radial rate ~2 re of a supercritical Hopf orbit (with 12/re in all
// shooting from a = 0.9, λ = 0.001, K = 8, r = 1.6 stalled at 3.4e-4 against its tolerance 1e-4).
std::optional<SearchRun> find_cycle(const ScanPlan& plan, const AggregationModel& model, std::span<const double> steady,
                                    double re, double im, ScanRecord& r) {
  if (!(re > 0.0)) return std::nullopt;
  if (!(im > 0.0)) {
    add_note(r, "the rightmost eigenvalue is real (an unstable node): no cycle around it is sought");
    return std::nullopt;
  }
  const double period = 2.0 * M_PI / im;
  const std::optional<SearchStart> begin = search_start(plan, model, steady, re, period, r);
  if (!begin) return std::nullopt;
  const std::vector<double>& from = begin->from;
  double settle = begin->settle;
  std::optional<SearchRun> search;
  try {
    // Far below the curve the cycle is a relaxation oscillation whose period is many times 2π/im (a = 1,
    // λ = 3.2e-4: ~840 against 107): a run that shows no oscillation is lengthened 4-fold up to cycle_run.
    // The start needs only to lie near the cycle (shooting refines it to its own rtol): 1e-6, the scan's
    // own runs' tolerance. At 1e-8 one run over relaxation oscillations to t ~ 1e5 took over 30 minutes.
    // Each run is bounded in CVODE steps (cycle_steps), not only in time: over relaxation oscillations at small
    // λ (a = 1, λ ≤ 1e-5) runs to t = 8000 at rtol 1e-6 took tens of minutes each.
    constexpr double search_rtol = 1e-6;
    const auto search_run = [&](double end) {
      try {
        return cycle_start_from_run(model, end, period / 50.0, search_rtol, from, long(plan.cycle_steps));
      } catch (const StepLimitReached& e) {  // other failures keep their own message
        throw std::runtime_error("the search run to t = " + shortest_text(end) + " needs more than cycle_steps = " +
                                 std::to_string(plan.cycle_steps) + " steps (" + e.what() + ")");
      }
    };
    std::optional<CycleStart> start = search_run(settle);
    while (!start && 4.0 * settle <= plan.cycle_run) {
      settle *= 4.0;
      start = search_run(settle);
    }
    if (!start) {
      add_note(r, "no cycle: the run to t = " + shortest_text(settle) + " does not oscillate");
      return std::nullopt;
    }
    search = classify_search_run(plan, *start, settle);
    // The scaled residual of the shooting equations to 1e-4 (periods to ~1e-5), and a bounded cost per point:
    // at most 8 Newton steps of at most 30 GMRES iterations (period maps); a start that needs more is reported.
    LimitCycleOptions options;
    options.tolerance = 1e-4;
    options.max_newton_iterations = 8;
    options.max_krylov_iterations = 30;
    const LimitCycle cycle = find_limit_cycle(model, start->state, start->period, options);
    if (!cycle.converged) {
      add_note(r, "no cycle: shooting from the run to t = " + shortest_text(settle) + " did not converge (" + cycle.note + ")");
      return search;
    }
    r.cycle_period = cycle.period;
    r.cycle_m0_min = cycle.m0_min;
    r.cycle_m0_max = cycle.m0_max;
    if (cycle.floquet_converged && !cycle.floquet.empty()) r.floquet_max = std::abs(cycle.floquet.front());
    r.cycle_stable = cycle.stable ? "yes" : "no";
  } catch (const std::runtime_error& e) {
    add_note(r, std::string("no cycle: ") + e.what());
  }
  return search;
}

// Linear stability of the point's steady state: an unstable steady state (Re μ > 0) means sustained
// oscillations; a stable one relaxes, through damped oscillations if the rightmost eigenvalue is complex.
std::optional<SearchRun> classify_by_stability(const ScanPlan& plan, AggregationModel model, double a, double lambda,
                                               bool cycles, ScanRecord& r) {
  const std::optional<SteadyStateResult> steady = branch_steady_state(plan, model, a, lambda, r);
  if (!steady) return std::nullopt;
  // A root whose mass piles up in the largest class is the truncation's, not the system's: at λN << 1 the
  // steady tail (n_k ∝ k^-a e^{-0.65 λ k}) lies beyond N, and under `drop` Newton then finds a state with all
  // the mass in class N draining at the leak rate (a = 0.95, λ = 1e-6, N = 2048: 99.9 % of the mass there).
  // A resolved tail (λN ≥ 8) puts ~1e-4 / N of the mass in that class.
  const std::vector<double> sizes = model.pivots();
  const double top = sizes.back() * steady->n.back() / total_mass(steady->n, sizes);
  if (top > 0.01) {
    add_note(r, "the steady state piles up at the truncation (" + shortest_text(top) +
                    " of the mass in the largest class): N too short for lambda");
    r.verdict = "unresolved";
    return std::nullopt;
  }
  r.mean_steady = 0;  // the classified moment Σ n_i x_i^p of the steady state
  for (std::size_t i = 0; i < sizes.size(); ++i) r.mean_steady += steady->n[i] * std::pow(sizes[i], plan.series_order);
  StabilityResult stability;
  try {
    stability = analyse_stability(model, steady->n);
  } catch (const std::runtime_error& e) {
    r.spectrum_converged = "no";
    r.verdict = "unresolved";
    add_note(r, std::string("spectrum: ") + e.what());
    return std::nullopt;
  }
  if (stability.rightmost.empty()) return std::nullopt;
  r.spectrum_converged = "yes";
  const std::complex<double> mu = stability.rightmost.front();
  r.rightmost_real = mu.real();
  r.rightmost_imag = std::abs(mu.imag());
  r.regime_stability = !stability.stable ? "sustained" : mu.imag() != 0 ? "damped" : "steady";
  if (!stability.stable && cycles) return find_cycle(plan, model, steady->n, mu.real(), std::abs(mu.imag()), r);
  return std::nullopt;
}

// The verdict of a point with a spectrum, once its run (the confirmation) is classified, and whether the two
// agree on sustained against relaxing.
void settle_verdict(ScanRecord& r) {
  if (r.spectrum_converged != "yes" || r.regime_stability.empty()) return;
  r.verdict = verdict_of(r, r.regime_stability != "sustained", r.rightmost_imag > 0);
  const bool known = r.regime == "sustained" || r.regime == "damped" || r.regime == "steady";
  if (known) r.agree = (r.regime == "sustained") == (r.regime_stability == "sustained") ? "yes" : "no";
}

// A confirmation run sized by the point's spectrum ([scan] confirm_run): its time grid and the classified
// tail, or why there is none.
struct Confirmation {
  TimeGrid time;
  double tail_fraction = 0;
  std::string why_not;  // non-empty: no run
};

// The run starts from the scene's initial state, so it first needs ~1/λ to relax towards the steady state
// (the shattering time; at small λ the transient is the coarsening of pure aggregation). Around a stable
// steady state μ = re ± i im it then relaxes for 6 e-folding times 6/|re| and 16 periods 2π/im, and is
// classified over as long again (the second half); around an unstable one, 12/re of growth away
// from it and 8 periods of the cycle (its shot period where found, else the cycle search run's, else 2π/im),
// of which the cycle part is classified. Outputs 25 per period (at most [time] every apart, at most 2·10^5 in all).
// `column_period`: the period of the cycle continued down the column to this point (NaN: none), used where the
// point shot no cycle of its own.
Confirmation confirmation_of(const ScanPlan& plan, const ScanRecord& r, const std::optional<SearchRun>& search,
                             double column_period) {
  Confirmation c;
  if (r.spectrum_converged != "yes" || !std::isfinite(r.rightmost_real)) {
    c.why_not = "not run: no spectrum to size a confirmation run by";
    return c;
  }
  const double re = r.rightmost_real, im = r.rightmost_imag;
  const bool focus = im > 0;
  const double period = std::isfinite(r.cycle_period)            ? r.cycle_period
                        : std::isfinite(column_period)            ? column_period
                        : search && std::isfinite(search->period) ? search->period
                        : focus                                   ? 2.0 * M_PI / im
                                                                  : NAN;
  const double relax = 1.0 / r.lambda;
  double settle = 0, window = 0;
  if (re < 0) {
    // Classified over as long again as it relaxed: a tail that is steady or still damped, not the transient
    // (at λ = 0.1 the oscillation dies within a few periods: a window right after it saw only the monotone
    // approach, and no converged decay).
    settle = std::max(6.0 / -re, focus ? 16.0 * period : 0.0);
    window = relax + settle;
  } else {
    settle = 12.0 / std::max(re, 1e-300);
    window = focus ? 8.0 * period : 12.0 / std::max(re, 1e-300);
  }
  const double end = relax + settle + window;
  if (!(end <= plan.confirm_run)) {
    c.why_not = "not run: a confirmation needs t = " + shortest_text(end) + " (1/lambda " + shortest_text(relax) +
                (re < 0 ? ", relaxation " : ", growth 12/Re mu ") + shortest_text(settle) + ", window " + shortest_text(window) +
                "), beyond confirm_run = " + shortest_text(plan.confirm_run);
    return c;
  }
  const std::vector<double>& scene_outputs = plan.scene.time.outputs;
  double every = scene_outputs.back() / double(scene_outputs.size());
  if (std::isfinite(period)) every = std::min(every, period / 25.0);
  every = std::min(every, window / 200.0);
  every = std::max(every, end / 2e5);
  const std::size_t count = std::size_t(std::ceil(end / every - 1e-9));
  for (std::size_t k = 1; k <= count; ++k) c.time.outputs.push_back(std::min(end, double(k) * end / double(count)));
  c.time.outputs.back() = end;
  c.time.end = end;
  c.tail_fraction = std::clamp(window / end, 16.0 / double(count), 1.0 - 1.0 / double(count));
  return c;
}

// The time series of the point's model over `time`, classified over `criteria`'s tail into r's run columns.
void classify_run(const ScanPlan& plan, Scene run, const OscillationCriteria& criteria,
                  const std::function<void(double t, double end)>& progress, ScanRecord& r) {
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
  if (progress) observer.progress = [&](double t) { progress(t, run.time.end); };
  plan.engine->run(run, observer);

  record_run(classify_oscillation(times, values, criteria), run.time.end, r);
}

// A relaxing verdict must be resolved by the run and the grid: the steady state that linear stability finds
// unstable (Re μ > 0) cannot relax, so a damped or steady time series there means the run is too short for
// the period (or the truncation too short for the tail); and a damped verdict whose own convergence check
// failed (too few cycles, a slow drift) is no verdict either, nor is a relaxation with no steady state to
// relax to (at λ far below 1/t_end the run sees the coarsening of pure aggregation, whose M0 decays
// monotonically, while the steady state's tail lies beyond the grid); nor a relaxation whose tail has not
// come near the steady state (the same coarsening where the steady state exists but is reached only after a
// time ~1/λ: the run is too short to show how it gets there). Such points are "unresolved": neither damped
// nor sustained.
void judge_relaxation_of(const ScanPlan& plan, ScanRecord& r) {
  if (!is_relaxing(r)) return;
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

}  // namespace

ScanRecord run_scan_point(const ScanPlan& plan, const ScanPoint& point, std::size_t size,
                          const std::function<void(double t, double end)>& progress, bool judge_relaxation) {
  const auto started = std::chrono::steady_clock::now();
  Scene run;  // the point's scene: the scan scene's model with this (a, λ, N) and its time grid
  run.name = plan.scene.name;
  run.model = point_model(plan, point.a, point.lambda, size);
  run.time = plan.scene.time;
  ScanRecord r;
  r.index = point.index;
  r.a = point.a;
  r.lambda = point.lambda;
  r.size = size;
  // The refined repeats (judge_relaxation false) only check a relaxing verdict: no cycles there. Nor where the
  // cycle continued down the column reached the point: near the curve a search of its own grows from the
  // unstable focus at Re μ and shooting converges slowly where the cycle attracts weakly (up to 2500 s a point
  // on the scan grid, against 5–70 s for the column's step to the same cycle).
  const bool from_column = std::isfinite(point.column_period);
  const bool cycles = plan.cycles && judge_relaxation && !from_column;
  OscillationCriteria criteria = plan.criteria;
  if (plan.stability && plan.confirm_run > 0) {
    // The evidence first, then a run as long as the spectrum says the confirmation needs.
    const std::optional<SearchRun> search = classify_by_stability(plan, run.model, point.a, point.lambda, cycles, r);
    const Confirmation c = confirmation_of(plan, r, search, point.column_period);
    if (c.why_not.empty()) {
      run.time = c.time;
      criteria.tail_fraction = c.tail_fraction;
      classify_run(plan, run, criteria, progress, r);
    } else if (search) {  // the cycle search's run off the steady state is the point's run
      add_note(r, c.why_not + "; the run is the cycle search's from the steady state to t = " + shortest_text(search->end) +
                      " (its second half classified)");
      record_run(search->classification, search->end, r);
    } else {
      r.regime = "not-run";
      add_note(r, c.why_not);
    }
  } else {
    classify_run(plan, run, criteria, progress, r);
    if (plan.stability) classify_by_stability(plan, run.model, point.a, point.lambda, cycles, r);
  }
  if (from_column && r.regime_stability == "sustained")
    add_note(r, "no cycle search of its own: the cycle continued down the column reached this point (period " +
                    shortest_text(point.column_period) + ")");
  settle_verdict(r);
  if (judge_relaxation) judge_relaxation_of(plan, r);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return r;
}

}  // namespace aggkit

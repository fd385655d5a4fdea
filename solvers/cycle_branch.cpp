#include "solvers/cycle_branch.hpp"

#include <algorithm>
#include <stdexcept>

#include "analysis/input_error.hpp"

namespace aggkit {

void CycleBranchOptions::validate() const {
  if (!(start_distance > 0.0 && start_distance <= 0.5))
    throw InputError("start_distance", format_value(start_distance), "a relative distance from lambda_crit in (0, 0.5]");
  if (!(step > 0.0 && step <= 2.0)) throw InputError("step", format_value(step), "a step in ln lambda in (0, 2]");
  if (!(relax_periods >= 6.0 && relax_periods <= 1000.0))
    throw InputError("relax_periods", format_value(relax_periods), "a number of periods in [6, 1000]");
  if (floquet_count < 0 || floquet_count > 50)
    throw InputError("floquet_count", std::to_string(floquet_count), "an integer in [0, 50]");
  shooting.validate();
}

HopfPoint hopf_on_branch(SteadyBranch& steady, const AggregationModel& base, double a, double lowest,
                         double relative_tolerance) {
  HopfPoint none;
  none.a = a;
  double above = 0.0;
  std::vector<double> above_state;
  for (std::size_t k = 0;; ++k) {
    const double lambda = steady.anchor_lambda() * std::exp(-double(k) * steady.step());
    if (lambda < lowest) {
      none.note = "the steady state stays stable (or has no complex pair crossing) down to lambda = " + format_value(lowest);
      return none;
    }
    const BranchSteadyState at = steady.at(lambda);
    if (!at.steady.converged) {
      none.note = "the steady branch ends at lambda = " + format_value(at.stopped_lambda) + " before a Hopf crossing";
      return none;
    }
    AggregationModel model = base;
    model.lambda = ShatteringRate::constant(lambda);
    const std::complex<double> pair = rightmost_complex_pair(analyse_stability(model, at.steady.n, 6).rightmost);
    if (pair.real() > 0.0) {
      if (above_state.empty()) {
        none.note = "the complex pair is already unstable at the anchor lambda = " + format_value(lambda);
        return none;
      }
      HopfOptions options;
      options.start = above_state;
      options.start_sizes = model.pivots();
      options.start_a = a;
      options.start_lambda = above;
      return locate_hopf(base, a, lambda, above, relative_tolerance, options);
    }
    above = lambda;
    above_state = at.steady.n;
  }
}

CycleBranch::CycleBranch(const AggregationModel& base, SteadyBranch& steady, double lambda_crit, CycleBranchOptions options)
    : base_(base), steady_(steady), lambda_crit_(lambda_crit), options_(std::move(options)) {
  if (!(lambda_crit > 0.0) || !std::isfinite(lambda_crit))
    throw InputError("lambda_crit", format_value(lambda_crit), "a finite shattering rate > 0");
  options_.validate();
  options_.shooting.floquet_count = 0;  // the nodes' multipliers are not needed
  lambda0_ = (1.0 - options_.start_distance) * lambda_crit_;
}

AggregationModel CycleBranch::model_at(double lambda) const {
  AggregationModel model = base_;
  model.lambda = ShatteringRate::constant(lambda);
  return model;
}

CycleBranch::Node CycleBranch::solve(const std::vector<double>& start, double period, double lambda, int previous_solves,
                                     double relax_periods) const {
  Node made;
  made.lambda = lambda;
  made.solves = previous_solves + 1;
  const AggregationModel model = model_at(lambda);
  std::vector<double> shoot_from = start;
  try {
    // The relaxation run: its last upward M0 crossing and the crossings' mean spacing start the shooting.
    const std::optional<CycleStart> relaxed =
        relax_periods > 0.0 ? cycle_start_from_run(model, relax_periods * period, period / 50.0, 1e-8, start) : std::nullopt;
    if (relaxed) {
      shoot_from = relaxed->state;
      period = relaxed->period;
    }
  } catch (const std::runtime_error& e) {
    made.note = "the prediction at lambda = " + format_value(lambda) + " cannot be integrated (" + e.what() + ")";
    return made;
  }
  made.cycle = find_limit_cycle(model, shoot_from, period, options_.shooting);
  made.converged = made.cycle.converged;
  if (!made.converged) made.note = "shooting did not converge at lambda = " + format_value(lambda) + " (" + made.cycle.note + ")";
  return made;
}

const HopfNormalForm& CycleBranch::normal_form() {
  if (formed_) return form_;
  formed_ = true;
  const BranchSteadyState steady = steady_.at(lambda0_);
  if (!steady.steady.converged) return form_;
  steady0_ = steady.steady.n;
  try {
    form_ = hopf_normal_form(model_at(lambda0_), steady0_);
  } catch (const std::runtime_error&) {
    form_ = HopfNormalForm{};
  }
  return form_;
}

CycleBranch::Node CycleBranch::first_node() {
  Node made;
  made.lambda = lambda0_;
  const HopfNormalForm& form = normal_form();
  if (steady0_.empty()) {
    made.note = "no steady state at lambda = " + format_value(lambda0_) + " to start the cycles from";
    return made;
  }
  if (form.q.empty()) {
    made.note = "no complex pair in the spectrum at lambda = " + format_value(lambda0_) + ": no Hopf normal form";
    return made;
  }
  if (!(form.mu.real() > 0.0)) {
    made.note = "the steady state at lambda = " + format_value(lambda0_) + " is stable (Re mu = " + format_value(form.mu.real()) +
                "): lambda_crit = " + format_value(lambda_crit_) + " is not above it on this grid";
    return made;
  }
  if (!form.supercritical()) {
    made.note = "subcritical Hopf bifurcation (first Lyapunov coefficient " + format_value(form.lyapunov) +
                " > 0): no small cycle below lambda_crit";
    return made;
  }
  // The amplitude's error decays by e^{-2 Re μ T} per period near the Hopf point (the normal form's radial
  // rate): enough periods to take it down by 1e3, at least relax_periods.
  const double period = 2.0 * M_PI / form.frequency();
  const double periods = std::clamp(std::log(1e3) / (2.0 * form.mu.real() * period), options_.relax_periods, 1000.0);
  return solve(form.cycle_point(steady0_), period, lambda0_, 0, periods);
}

namespace {

// The secant y1 + (y1 − y0) r, kept positive (shifted_density).
double secant(double y0, double y1, double r) { return shifted_density(y1, r * (y1 - y0)); }

}  // namespace

CycleBranch::Node CycleBranch::step(const Node& before, const Node* earlier, double lambda1) {
  Node last;
  for (int parts : {1, 2, 4}) {
    Node from = before;
    const Node* previous = earlier;
    Node kept;  // the sub-step before `from`, once there is one
    last = Node{};
    for (int p = 1; p <= parts; ++p) {
      const double lambda = std::exp(std::log(before.lambda) + double(p) / parts * (std::log(lambda1) - std::log(before.lambda)));
      std::vector<double> start = from.cycle.state;
      double period = from.cycle.period;
      if (previous) {
        const double r = std::log(lambda / from.lambda) / std::log(from.lambda / previous->lambda);
        for (std::size_t k = 0; k < start.size(); ++k) start[k] = secant(previous->cycle.state[k], from.cycle.state[k], r);
        period = secant(previous->cycle.period, from.cycle.period, r);
      } else {
        // From the first cycle: the normal form's law, the deviation from the steady state ∝ sqrt(λ_crit − λ).
        const BranchSteadyState steady = steady_.at(lambda);
        if (!steady.steady.converged) {
          last.note = "no steady state at lambda = " + format_value(lambda) + " to carry the first cycle to";
          break;
        }
        const double grow = std::sqrt((lambda_crit_ - lambda) / (lambda_crit_ - from.lambda));
        for (std::size_t k = 0; k < start.size(); ++k)
          start[k] = shifted_density(steady.steady.n[k], grow * (from.cycle.state[k] - steady0_[k]));
      }
      last = solve(start, period, lambda, from.solves, options_.relax_periods);
      if (!last.converged) break;
      kept = std::move(from);
      from = last;
      previous = &kept;
    }
    if (last.converged) return last;
  }
  return last;
}

const CycleBranch::Node& CycleBranch::node(std::size_t k) {
  if (auto found = nodes_.find(k); found != nodes_.end()) return found->second;
  Node made;
  if (k == 0) {
    made = first_node();
  } else {
    const Node& above = node(k - 1);
    if (!above.converged) {
      made = above;  // the walk stopped above: every node below inherits where and why
    } else {
      const Node* earlier = k >= 2 ? &node(k - 2) : nullptr;
      made = step(above, earlier, lambda0_ * std::exp(-double(k) * options_.step));
    }
  }
  return nodes_.emplace(k, std::move(made)).first->second;
}

BranchCycle CycleBranch::at(double lambda) {
  if (!(lambda > 0.0) || !std::isfinite(lambda))
    throw InputError("lambda", format_value(lambda), "a finite shattering rate > 0");
  BranchCycle result;
  if (lambda > lambda0_ * (1.0 + 1e-12)) {
    result.note = "lambda = " + format_value(lambda) + " lies within " + format_value(options_.start_distance) +
                  " lambda_crit of the Hopf point, above the branch's first cycle";
    return result;
  }
  const std::size_t k = std::size_t(std::floor(std::log(lambda0_ / lambda) / options_.step + 1e-9));
  const Node& above = node(k);
  const double node_lambda = lambda0_ * std::exp(-double(k) * options_.step);
  Node reached = above;
  if (above.converged) {
    const LimitCycleOptions at_nodes = options_.shooting;
    options_.shooting.floquet_count = options_.floquet_count;
    if (std::abs(std::log(lambda / node_lambda)) < 1e-12) {
      // λ on a node: the node's cycle again, now with its multipliers (Newton returns at once).
      reached = solve(above.cycle.state, above.cycle.period, lambda, above.solves, 0.0);
    } else {
      reached = step(above, k >= 1 ? &node(k - 1) : nullptr, lambda);
    }
    options_.shooting = at_nodes;
  }
  result.cycle = reached.cycle;
  result.solves = reached.solves;
  result.how = "from the Hopf normal form at lambda = " + format_value(lambda0_) + ", continued in " +
               std::to_string(reached.solves) + " shooting solves";
  if (!reached.converged) {
    std::size_t last = k;
    while (last > 0 && !node(last).converged) --last;
    if (node(last).converged) result.stopped_lambda = node(last).lambda;
    result.note = reached.note;
  }
  return result;
}

}  // namespace aggkit

#include "solvers/steady_branch.hpp"

#include <algorithm>

#include "analysis/input_error.hpp"

namespace aggkit {

namespace {

bool negative_root_note(const std::string& note) { return note.find("negative densities") != std::string::npos; }

}  // namespace

SteadyBranch::SteadyBranch(const AggregationModel& base, double anchor_lambda, double step, SteadyStateOptions options)
    : base_(base), anchor_(anchor_lambda), step_(step), options_(std::move(options)) {
  if (!(anchor_lambda > 0.0) || !std::isfinite(anchor_lambda))
    throw InputError("anchor_lambda", format_value(anchor_lambda), "a finite shattering rate > 0");
  if (!(step > 0.0 && step <= 2.0)) throw InputError("step", format_value(step), "a step in ln lambda in (0, 2]");
  options_.validate();
  newton_only_ = options_;
  newton_only_.start_retries = 0;
}

AggregationModel SteadyBranch::model_at(double lambda) const {
  AggregationModel model = base_;
  model.lambda = ShatteringRate::constant(lambda);
  return model;
}

SteadyBranch::Node SteadyBranch::step(const Node& from, double lambda0, double lambda1) const {
  Node last;
  for (int parts : {1, 2, 4}) {
    std::vector<double> guess = from.n;
    last = Node{};
    last.steps = from.steps;
    for (int p = 1; p <= parts; ++p) {
      const double lambda = std::exp(std::log(lambda0) + double(p) / parts * (std::log(lambda1) - std::log(lambda0)));
      last.steady = solve_steady_state(model_at(lambda), newton_only_, guess);
      ++last.steps;
      if (!last.steady.converged) break;
      guess = last.steady.n;
    }
    if (last.steady.converged) {
      last.converged = true;
      last.n = last.steady.n;
      return last;
    }
  }
  last.negative_root = negative_root_note(last.steady.note);
  last.note = last.steady.note;
  return last;
}

const SteadyBranch::Node& SteadyBranch::node(std::size_t k) {
  if (auto found = nodes_.find(k); found != nodes_.end()) return found->second;
  Node made;
  if (k == 0) {
    made.steady = solve_steady_state(model_at(anchor_), options_);
    made.steps = 1;
    made.converged = made.steady.converged;
    made.n = made.steady.n;
    made.note = made.steady.note;
    made.negative_root = !made.converged && negative_root_note(made.note);
  } else {
    const Node& above = node(k - 1);
    if (!above.converged) {
      made = above;  // the walk stopped above: every node below inherits where and why
    } else {
      made = step(above, anchor_ * std::exp(-double(k - 1) * step_), anchor_ * std::exp(-double(k) * step_));
    }
  }
  return nodes_.emplace(k, std::move(made)).first->second;
}

BranchSteadyState SteadyBranch::at(double lambda) {
  if (!(lambda > 0.0) || !std::isfinite(lambda))
    throw InputError("lambda", format_value(lambda), "a finite shattering rate > 0");
  BranchSteadyState result;
  if (lambda >= anchor_) {
    result.steady = solve_steady_state(model_at(lambda), options_);
    result.steps = 1;
    result.how = "newton from a CVODE start";
    if (!result.steady.converged) {
      result.note = result.steady.note;
      result.negative_root = negative_root_note(result.note);
    }
    return result;
  }
  // The last ladder node at or above λ (a small tolerance keeps a λ on a node from stepping from the one above).
  const std::size_t k = std::size_t(std::floor(std::log(anchor_ / lambda) / step_ + 1e-9));
  const Node& above = node(k);
  const double node_lambda = anchor_ * std::exp(-double(k) * step_);
  const Node reached = above.converged ? step(above, node_lambda, lambda) : above;
  result.steps = reached.steps;
  result.how = "continuation from lambda = " + format_value(anchor_) + " in " + std::to_string(reached.steps) + " Newton solves";
  result.steady = reached.steady;
  result.steady.converged = reached.converged;
  if (!reached.converged) {
    // Where the walk stopped: the deepest node reached (NaN: not even the anchor's steady state was found).
    std::size_t last = k;
    while (last > 0 && !node(last).converged) --last;
    if (node(last).converged) result.stopped_lambda = anchor_ * std::exp(-double(last) * step_);
    result.negative_root = reached.negative_root;
    result.note = reached.note;
  }
  return result;
}

}  // namespace aggkit

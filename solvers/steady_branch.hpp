#pragma once
// The steady state of a model at any shattering rate λ by natural-parameter continuation in ln λ from an
// anchor λ_a where Newton converges from the solver's own start (a CVODE relaxation; solvers/steady_state.hpp).
// Below λ_a the relaxation that CVODE would have to follow takes ~1/λ and the start fails; from a root on the
// branch one step away Newton converges in a few iterations, as the Hopf search does down to λ ~ 1e-11
// (solvers/hopf.cpp).
//
// The path is a fixed ladder: the nodes λ_a e^{-k h} (k = 1, 2, ...) down to the last node above λ, then λ
// itself, each solved by Newton from the root at the node before (no other start: a failed step means the
// positive branch is lost, and another start could land on another root of the truncated system). A step that
// fails is retried as two half steps, then four quarter steps. So the state at λ depends only on (model, λ_a,
// h, λ), never on which other λ were asked first: a scan gives the same rows on any number of ranks. The nodes
// are memoised, so a row of λ values costs one walk down.
//
// Where the walk stops (no positive root from the node above, even in quarter steps) the point below has no
// steady state reached by this path: the result says at which λ it stopped and why — on a graded grid at very
// small λ the roots go negative at the steep front (no positive steady state on that grid), which the note
// names.
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "solvers/model.hpp"
#include "solvers/steady_state.hpp"

namespace aggkit {

struct BranchSteadyState {
  SteadyStateResult steady;       // converged = a positive steady state at λ was reached
  std::string how;                // "newton from a CVODE start" | "continuation from lambda = ... in K steps"
  int steps = 0;                  // Newton solves on the way (nodes and the last step, retries included)
  double stopped_lambda = std::numeric_limits<double>::quiet_NaN();  // the last λ reached, where the walk stopped
  bool negative_root = false;     // the walk stopped because the next root has negative densities
  std::string note;               // why it stopped
};

class SteadyBranch {
 public:
  // `base`: the model (its λ is replaced); anchor_lambda λ_a > 0; step h in ln λ (0 < h ≤ 2).
  // Throws InputError for a bad anchor or step.
  SteadyBranch(const AggregationModel& base, double anchor_lambda, double step = 0.5,
               SteadyStateOptions options = {});

  // The steady state at λ > 0: by Newton from the solver's own start at λ ≥ λ_a, else down the ladder.
  BranchSteadyState at(double lambda);

  double anchor_lambda() const { return anchor_; }
  double step() const { return step_; }  // h: the ladder's nodes are anchor_lambda() e^{-k h}

 private:
  struct Node {
    bool converged = false;
    std::vector<double> n;
    SteadyStateResult steady;
    std::string note;
    bool negative_root = false;
    int steps = 0;  // Newton solves from the anchor to here
  };
  AggregationModel model_at(double lambda) const;
  const Node& node(std::size_t k);  // node k: λ_a e^{-k h}; node 0 the anchor
  // Newton from `from` (a root at λ0) to λ1 in 1, 2 or 4 equal steps in ln λ.
  Node step(const Node& from, double lambda0, double lambda1) const;

  AggregationModel base_;
  double anchor_, step_;
  SteadyStateOptions options_, newton_only_;
  std::map<std::size_t, Node> nodes_;
};

}  // namespace aggkit

#pragma once
// The branch of limit cycles born at the Hopf point, followed in λ away from it: computed directly by
// shooting (solvers/limit_cycle.hpp), never waited for. Below λ_crit the periods reach 10^3..10^9 and the
// growth away from the unstable steady state takes ~1/Re μ, so a run that settles on the cycle is out of
// reach for all but the points nearest the curve; the branch needs none.
//
// Start: at λ_0 = (1 − δ) λ_crit (δ = 0.02) the Hopf normal form (solvers/hopf_normal_form.hpp) predicts the
// cycle, n* + 2ρ Re q with period 2π/(Im μ + Im c1 ρ²); shooting corrects it. Where the bifurcation is
// subcritical (l1 > 0) the normal form predicts no cycle on this side and the branch says so.
// Ladder: nodes λ_k = λ_0 e^{-k h} (h in ln λ), each cycle solved from a prediction made of the two cycles
// before it (a secant in ln n and ln T against ln λ; from node 0 to node 1, the normal form's law: the
// deviation from the steady state scaled by sqrt((λ_crit − λ)/(λ_crit − λ_0))). A failed step is retried as two
// half steps, then four quarter steps. As in solvers/steady_branch.hpp the cycle at λ depends only on (model,
// λ_crit, h, λ), never on which λ were asked first, and the nodes are memoised, so a column of λ values of a
// scan costs one walk down. Where the walk stops, the λ below it say where and why.
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "solvers/hopf_normal_form.hpp"
#include "solvers/limit_cycle.hpp"
#include "solvers/model.hpp"
#include "solvers/stability.hpp"
#include "solvers/steady_branch.hpp"

namespace aggkit {

struct BranchCycle {
  LimitCycle cycle;               // converged = a cycle at λ was reached (Floquet multipliers computed at λ)
  std::string how;                // "from the Hopf normal form at lambda = ..., continued in K shooting solves"
  int solves = 0;                 // shooting solves on the way (retries included)
  double stopped_lambda = std::numeric_limits<double>::quiet_NaN();  // the last λ reached, where the walk stopped
  std::string note;               // why there is no cycle at λ
};

struct CycleBranchOptions {
  double start_distance = 0.02;   // δ: the first cycle at (1 − δ) λ_crit
  double step = 0.25;             // h, in ln λ
  // Each prediction is first carried along the flow over this many predicted periods (CVODE), and shooting
  // starts from the run's last upward M0 crossing with the crossings' mean spacing as the period
  // (cycle_start_from_run): Newton–Krylov shooting reaches its tolerance from a start on the attracting cycle to
  // ~1e-4 but stalls at scaled residuals of 1e-4..1e-2 from predictions with percent errors (the finite-difference
  // J·v limits it). At the first cycle the count is raised until the normal form's radial decay e^{-2 Re μ T}
  // per period takes the amplitude's error down by 1e3.
  double relax_periods = 12.0;
  // Shooting at the nodes (their Floquet multipliers are not computed): the scaled residual to 5e-4 in at most
  // 8 Newton steps of at most 40 GMRES iterations (period maps) each. From a relaxed start Newton converges
  // only linearly below ~1e-4 (the far tail's relative residual; brownian a = 0.95 at 0.95 λ_crit: 8 steps
  // left 7e-5 while the period had settled to 2e-7), and at 3.7e-4 the period is within 2e-6 of the
  // converged one.
  LimitCycleOptions shooting = [] {
    LimitCycleOptions o;
    o.tolerance = 5e-4;
    o.max_newton_iterations = 8;
    o.max_krylov_iterations = 40;
    return o;
  }();
  int floquet_count = 4;          // at the λ asked for
  void validate() const;          // throws InputError naming the option
};

// λ_crit on the steady branch's own grid, for the brownian kernel with exponent a: the branch's ladder nodes
// from its anchor down to the first whose rightmost complex pair has Re μ > 0 (none below `lowest`), then
// Brent's method (locate_hopf, solvers/stability.hpp) between it and the node above, from the node above's
// steady state, to relative_tolerance. found = false, with the note, where there is no such crossing.
HopfPoint hopf_on_branch(SteadyBranch& steady, const AggregationModel& base, double a, double lowest,
                         double relative_tolerance = 1e-6);

class CycleBranch {
 public:
  // `base`: the model (λ replaced); `steady`: the steady branch of the same model; λ_crit the Hopf point
  // (cycles for λ < λ_crit). Throws InputError for a bad λ_crit or options.
  CycleBranch(const AggregationModel& base, SteadyBranch& steady, double lambda_crit, CycleBranchOptions options = {});

  // The cycle at λ ≤ λ_0, with its Floquet multipliers. λ > λ_0: none (note says so).
  BranchCycle at(double lambda);

  // The normal form at λ_0 (computed on the first call of `at`); empty q where it failed.
  const HopfNormalForm& normal_form();
  double start_lambda() const { return lambda0_; }

 private:
  struct Node {
    bool converged = false;
    LimitCycle cycle;
    double lambda = 0;
    std::string note;
    int solves = 0;
  };
  AggregationModel model_at(double lambda) const;
  const Node& node(std::size_t k);
  Node first_node();
  // The cycle at λ1 from the nodes `before` (at λ) and `earlier` (its predecessor; nullptr at node 0), in 1, 2
  // or 4 steps.
  Node step(const Node& before, const Node* earlier, double lambda1);
  // Relaxation over relax_periods · period (0: none), then shooting.
  Node solve(const std::vector<double>& start, double period, double lambda, int previous_solves, double relax_periods) const;

  AggregationModel base_;
  SteadyBranch& steady_;
  double lambda_crit_, lambda0_;
  CycleBranchOptions options_;
  bool formed_ = false;
  HopfNormalForm form_;
  std::vector<double> steady0_;   // the steady state at λ_0
  std::map<std::size_t, Node> nodes_;
};

}  // namespace aggkit

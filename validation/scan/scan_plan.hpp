#pragma once
// A scan scene (`aggkit scan SCENE --out DIR`): the (a, λ) grid of the Brownian-type kernel
// K_ij = (i/j)^a + (j/i)^a over which each point's oscillation regime is classified. Schema:
//
//   name = "..."
//   tier = "full"  optional: the `aggkit validate` tier, as in a run scene (default fast)
//   [model]     as in a run scene (scene.hpp); kernel must be { name = "brownian", a = .. }: each point
//               replaces a and λ (the model's own values are only placeholders); size N, truncation, initial
//   [time]      end and outputs/every: each point's CVODE run (sample often enough: >= 8 outputs per period,
//               and uniformly — `every` — since the classifier needs a uniform series)
//   [[engine]]  optional, at most one, name = "cvode": the integrator options of every point
//   [scan]
//   a = [0.9, 0.95]                       a list (increasing, each in [0, 1]) or { from, to, count }
//   lambda = { from = 1e-3, to = 0.1, count = 9, spacing = "log" }   λ > 0; spacing linear (default) | log
//   series = "M0"                         the moment classified: M0 (default) or M2
//   tail = 0.5                            fraction of the run classified (the rest is transient); default 0.5
//   stability = true                      also steady state + linear stability where available (default)
//   steady_match = 0.05                   a damped or steady verdict needs the tail's mean within this
//                                         fraction of the steady state's value (the run reached it); else
//                                         the point is unresolved (default 0.05)
//   refine = true                         repeat every damped or steady point on the refined grid (2N;
//                                         graded: also (r - 1)/2); the verdict stands only if the
//                                         repeat relaxes too and its steady state is stable, else the
//                                         point is unresolved (default true)
//   cycles = true                         the attracting cycle around every unstable steady state by
//                                         shooting (period, M0 range, Floquet multipliers); a stable one
//                                         makes the point sustained (default true)
//   cycle_run = 1e5                       the longest run that starts a cycle search (its length comes from
//                                         the spectrum: 16 linear periods, 24 e-folding times from the
//                                         steady state); a point that needs more stays "unstable", and
//                                         says so (default 1e5)
//   cycle_steps = 40000                   the most CVODE steps one run of a cycle search may take: far
//                                         below the curve the cycles are relaxation oscillations whose
//                                         bursts cost thousands of steps each; a search that needs more
//                                         stops, and the point says where (default 40000)
//   cycle_column = 12                     with stability and cycles: the attracting cycle continued down each
//                                         a's column of λ below the Hopf point (scan_cycle_column.hpp), each
//                                         step a run of this many predicted periods (at least 10: its second
//                                         half must hold the 4 cycles a converged verdict needs) from the
//                                         cycle of the λ above, at most column_steps CVODE steps. The columns
//                                         are walked before the points: a point its column reached seeks no
//                                         cycle of its own and takes the column's sustained run as its
//                                         evidence (as does a point whose own search found none). Needs
//                                         series = "M0". Absent: no columns
//   column_steps = 120000                 the most CVODE steps one run of a column's step may take (default
//                                         cycle_steps): far below the curve a period costs ~2000–3000 steps
//                                         (a = 0.75: 2150 at λ = 1e-6, 2870 at 3.16e-8). Not part of the
//                                         points' fingerprint; a step the budget stopped is run again under
//                                         another budget
//   confirm_run = 2e4                     with stability: each point's run is a confirmation whose length
//                                         comes from the point's spectrum, not from [time] end: 1/λ for the
//                                         relaxation from the initial state and 6 e-folding times 6/|Re μ|
//                                         and 16 periods of a stable steady state, classified over as long
//                                         again; or 1/λ, 12/Re μ of growth and 8 periods of the cycle around
//                                         an unstable one, classified over those periods (the cycle search's
//                                         run stands in where it is not run). A point whose confirmation
//                                         needs more than confirm_run time units is not run (regime
//                                         "not-run", the length in its note); [time] every is the largest
//                                         output spacing.
//                                         Absent: every point runs over [time] (the time series classifies)
//   truncation_check = { points = [[0.95, 0.01]], lambda_crit = true }
//                                         repeat these points (and λ_crit(a)) at size 2N (optional)
//   hopf_grid = { resolved = 256, ratio = 1.005 }   the size grid of λ_crit(a) (default: the model's grid).
//                                         A graded one (solvers/size_grid.hpp) makes λ_crit(a) the converged
//                                         curve (solvers/hopf_curve.hpp: N doubled until it moves ≤ 1 %, then
//                                         checked with K doubled and r - 1 halved) instead of one N
//
// No [observe] or [compare]: a scan writes its own outputs (scan_output.hpp). Unknown keys are errors.
#include <cstddef>
#include <limits>
#include <filesystem>
#include <string>
#include <string_view>
#include <memory>
#include <utility>
#include <vector>

#include "analysis/oscillation.hpp"
#include "validation/engines/engine.hpp"
#include "validation/scene/scene.hpp"

namespace aggkit {

struct ScanPoint {
  std::size_t index = 0;  // a-major: index = i_a * lambda_count + i_λ
  double a = 0, lambda = 0;
  // The period of the attracting cycle continued down this a's column to this λ (validation/scan/
  // scan_cycle_column.hpp), where the column reached it; the point then seeks no cycle of its own (the column's
  // run is its evidence) and sizes its confirmation run by this period. NaN: the point seeks its own.
  double column_period = std::numeric_limits<double>::quiet_NaN();
};

class SteadyBranches;  // validation/scan/scan_point.cpp

struct ScanPlan {
  Scene scene;                        // model (brownian), time grid and exactly one cvode engine
  std::shared_ptr<const Engine> engine;  // that engine, built
  std::vector<double> a, lambda;      // increasing
  bool lambda_log = false;            // λ spaced logarithmically (λ_crit from the grid: geometric midpoint)
  std::string series = "M0";          // M0 or M2
  double series_order = 0;            // its p
  OscillationCriteria criteria;       // tail_fraction from `tail`
  bool stability = true;
  double steady_match = 0.05;         // largest |tail mean - steady value| / steady value of a relaxing verdict
  bool refine = true;                 // relaxing verdicts repeated on refined_plan()
  bool cycles = true;                 // the attracting cycle of every unstable point by shooting
  double cycle_run = 1e5;             // the longest run a cycle's start may take (time units)
  std::size_t cycle_steps = 40000;    // the most CVODE steps of one run of a cycle search
  std::size_t column_periods = 0;     // > 0: the cycles continued down each column, runs of this many periods
  std::size_t column_steps = 0;       // the most CVODE steps of one run of a column's step (0: cycle_steps)
  std::size_t column_step_budget() const { return column_steps > 0 ? column_steps : cycle_steps; }
  double confirm_run = 0;             // > 0: confirmation runs sized by the spectrum, at most this long
  std::vector<std::pair<double, double>> check_points;  // (a, λ) repeated at 2N
  bool check_lambda_crit = false;                       // λ_crit(a) repeated at 2N
  SizeGrid hopf_grid;                                   // the grid of λ_crit(a) (the model's by default)
  // Everything a finished point's result depends on except (a, λ): a resumed scan reuses the points only
  // if this is unchanged.
  std::string fingerprint;
  // The steady-state branches walked so far in this process, one per (a, N, grid), shared by the plan's
  // copies (refined_plan): each point's steady state comes by continuation in λ from the scan's largest λ
  // (solvers/steady_branch.hpp), and a row of λ values costs one walk.
  std::shared_ptr<SteadyBranches> branches;

  std::size_t point_count() const { return a.size() * lambda.size(); }
  ScanPoint point(std::size_t index) const { return {index, a[index / lambda.size()], lambda[index % lambda.size()]}; }
  std::size_t size() const { return scene.model.size; }
};

// Reads and validates a scan scene; InputError names the key, the value and what is allowed.
ScanPlan load_scan_plan(const std::filesystem::path& path);
ScanPlan parse_scan_plan(std::string_view text, const std::string& source = "scene");

// The model of one point: the scene's with the kernel's a, a constant λ and truncation size `size`.
AggregationModel point_model(const ScanPlan& plan, double a, double lambda, std::size_t size);

// The plan of the refined repeats: a graded grid with r - 1 halved (a uniform grid as it is; the repeat's N
// is doubled by the caller). Not K: on the scan's grids doubling K moves λ_crit by ≤ 6e-5, halving r - 1 by
// up to 8e-4, and 2K would add K classes to a pair table that grows as their square. The run's length is checked within the run itself: a relaxing
// verdict needs the tail at the steady state (steady_match) and, if damped, a converged decay.
ScanPlan refined_plan(const ScanPlan& plan);

}  // namespace aggkit

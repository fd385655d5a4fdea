#include "validation/scan/scan_cycle_column.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <numeric>
#include <optional>
#include <sstream>

#include "analysis/oscillation.hpp"
#include "analysis/text.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/cycle_extrapolation.hpp"
#include "solvers/discretisation.hpp"
#include "solvers/hopf_normal_form.hpp"
#include "solvers/limit_cycle.hpp"
#include "solvers/mass_constrained_system.hpp"
#include "solvers/size_grid.hpp"
#include "solvers/steady_branch.hpp"
#include "validation/io/atomic_file.hpp"
#include "validation/runs/mpi_ranks.hpp"
#include "validation/runs/run_store.hpp"
#include "validation/scan/scan_column_files.hpp"

namespace aggkit {
namespace {

constexpr double start_fraction = 0.95;  // the first cycle, on the normal form's, at 0.95 λ_crit (as the criticality)
// Where the normal form's cycle attracts so weakly that relaxing to it takes more than this many periods, the first
// step starts from the point that reduced rank extrapolation of its returns reaches (solvers/cycle_extrapolation.hpp)
// where its last jump was at most `extrapolation_taken` (relative): a = 0.6 at 0.95 λ_crit needs ~1000 periods of
// ~5400 CVODE steps, the extrapolation ~20 returns (brownian a = 0.95 at 0.99 λ_crit, graded K = 32: 20 returns
// against 409 periods, tests/solvers/test_cycle_extrapolation.cpp).
constexpr double extrapolate_beyond = 32.0;
constexpr double extrapolation_taken = 1e-3;
constexpr double branch_anchor = 0.1;    // as the scan points' steady branches (scan_point.cpp)
constexpr double search_rtol = 1e-6;     // as the points' cycle searches (scan_point.cpp)
// The absolute tolerances of a column's runs, relative to the unit monodisperse start: atol_k = atol / k^3
// (IntegratorOptions), at least the floor and at most atol_mass · M / x_k, tried in turn; a step starts at the
// level of the step above (the quiescent phase only deepens down the column). Measured from the cached state of
// the cycle at a = 0.75, λ = 1.78e-6, 12 periods at λ = 1e-6 (bench_column_step; bench/results/RESULTS.md,
// "The monomer's tolerance and the far tail's mass"):
// - atol at n_1. At the integrator's default, rtol/100 = 1e-8, the monomers are not resolved in the quiescent
//   phase far below the curve (n_1 ~ 1e-9): n_1 wandered to -3e-9 and the run never burst again (the floors
//   1e-8 … 1e-12 of the earlier ladder alike: a floor bounds only the large sizes' tolerances).
// - atol_mass. With a floor of 1e-14 a far-tail class of the graded grid (x up to 2^40) may hold junk worth
//   1e-2 of the mass; in a burst the Newton corrections spread it, the leak through N swung by 1e-4 a burst, and
//   the mass projection moved n_1 to -5e-4. Bounded to 1e-15 of the mass a class, the run kept its mass.
// - The levels. Read at the internal steps (as the columns read M0, Column::classify), 1e-16/1e-16/1e-15 and
//   1e-16/1e-16/1e-18 agree: period 312379.8 both, M0's troughs 9.12545e-5 and 9.12544e-5 in every period;
//   16700 CVODE steps against 25847 (43 s against 66 s). (Read at the outputs, which are projected onto the
//   mass shell while the steps below atol 1e-10 are not, the troughs wander: 5.9e-5 … 3.9e-5 at atol_mass
//   1e-15 and 1.16e-4 at 1e-18, since the projection hands the steps' mass defect to the smallest sizes, which
//   in the quiescent phase hold almost none of M0.) Next to the curve the level costs what the earlier floor
//   1e-8 did (a = 0.75, λ = 3.16e-4: 12 s against 13.7 s, the same period to 6e-5).
struct ColumnTolerance {
  double atol, floor, mass;
  RunTolerance run() const { return {.atol = atol, .atol_floor = floor, .atol_mass = mass}; }
  std::string text() const {
    return "atol " + shortest_text(atol) + " with floor " + shortest_text(floor) + " and atol_mass " + shortest_text(mass);
  }
};
constexpr std::array<ColumnTolerance, 2> column_tolerances = {{{1e-16, 1e-16, 1e-15}, {1e-16, 1e-16, 1e-18}}};
// The largest relative gain of the mass Σ x_i N_i over a run that is taken, against the model's initial mass
// (the shell the integrator holds Σ x_i N_i + L on; Column::shell_mass_). Aggregation and shattering keep
// the mass and drop truncation only removes it, so a gain is the integrator's error alone: the leaked mass,
// integrated beside the densities with their sum kept on M (solvers/cvode_integrator.hpp), goes negative where
// a floor is too coarse for the densities (a = 0.75, λ = 1.78e-6, floor 1e-8: +3.3 % over the quiescent phase).
// A loss is legitimate (on a coarse grid up to N = 2^20 the cycles leak 0.5 % a run) and is not bounded here.
constexpr double mass_gain_limit = ColumnCycle::mass_gain_limit;
// Outputs a predicted period: the crossings and peaks are read from them. Far below the curve a relaxation
// burst is a few hundredths of a period wide: at 50 outputs a period (a = 0.85, λ = 3.16e-5, period 9486) the
// sampled peaks ranged over 0.033 … 0.060, the mid-range crossing was missed in 2 of 7 periods and the others
// varied by 1 %; at 400 the periods agree to 1.5e-4 and every crossing is found. At 50 the columns at a = 0.9
// and 0.95 stopped at λ = 1.78e-4 and 3.16e-4 on periods that seemed modulated (1647 … 1666 recurring every
// 4.3 periods at a = 0.9: the beat of the sampling phase, T/Δ = 49.23); at 400 both steps settled (periods
// 1653.94 and 889.46). The outputs cost an interpolation and a copy of the state each, far less than the
// ~1100 CVODE steps a period there.
constexpr double outputs_per_period = 400;
const double largest_step = std::sqrt(10.0);  // the largest ratio of consecutive λ of a column

class Column {
 public:
  Column(const ScanPlan& plan, const std::filesystem::path& points, double a, double lambda_crit)
      : plan_(plan), points_(points), a_(a), grid_(point_model(plan, a, branch_anchor, plan.size()).grid.describe()) {
    const std::unique_ptr<Discretisation> classes = make_discretisation(point_model(plan, a, branch_anchor, plan.size()));
    shell_mass_ = total_mass(classes->initial_state(), classes->sizes());
    nodes_.push_back(start_fraction * lambda_crit);
    std::vector<double> below;
    for (double l : plan.lambda)
      if (l < nodes_.front()) below.push_back(l);
    std::sort(below.rbegin(), below.rend());
    // Between the grid's λ, geometric steps of at most a factor 10^(1/2). At the integrator's default atol and
    // the earlier floors such a step stalled CVODE in the transient from the cycle above (a = 0.75, λ = 1e-3 to
    // 3.2e-4: 40000 steps reached t = 61), and the columns went through midpoints 10^(1/4) apart; at the
    // column_tolerances it takes 4428 steps and settles on the period of the steps through the midpoint to 7e-6
    // (1209.785 against 1209.777; a = 0.8, 3.16e-3 to 1e-3: 374.012 against 374.005; a = 0.75, 1e-6 to 3.16e-7:
    // 972304 against 972297, 80 s), so a column costs half the runs.
    for (double lambda : below) {
      const double above = nodes_.back();
      const int steps = int(std::ceil(std::log(above / lambda) / std::log(largest_step) - 1e-9));
      for (int k = 1; k < steps; ++k) nodes_.push_back(above * std::pow(lambda / above, double(k) / steps));
      nodes_.push_back(lambda);
    }
  }

  // The cached steps, in walking order: a prefix of the nodes, ending at the first that stopped the walk.
  std::vector<ColumnCycle> cached() const {
    std::vector<ColumnCycle> done;
    for (double lambda : nodes_) {
      const auto c = parse_file(read_text_file(file(lambda, ".csv")), a_, lambda, plan_.column_periods, grid_,
                                plan_.column_step_budget());
      if (!c) break;
      done.push_back(*c);
      parse_floquet(read_text_file(file(lambda, "_floquet.csv")), done.back());
      if (!c->sustained()) break;
    }
    return done;
  }

  // The λ the column walks (its first cycle's, then the plan's below it with the geometric steps between), and a.
  std::size_t nodes() const { return nodes_.size(); }
  double a() const { return a_; }

  bool finished() const {
    const std::vector<ColumnCycle> done = cached();
    const bool measured = std::none_of(done.begin(), done.end(), [&](const ColumnCycle& c) { return wants_floquet(c) && !c.floquet_done; });
    return !done.empty() && (!done.back().sustained() || done.size() == nodes_.size()) && measured;
  }

  // Walks on from the last cached step. False (reported) where a step threw, e.g. could not be written: the
  // column is then unfinished and a rerun walks on from its last cached step.
  bool walk(std::ostream* progress, int rank) {
    try {
      walk_on(progress, rank);
      return true;
    } catch (const std::exception& e) {
      if (progress)
        *progress << "aggkit scan: [rank " << rank << "] cycle column a = " << shortest_text(a_) << " failed: " << e.what()
                  << "\n" << std::flush;
      return false;
    }
  }

 private:
  void walk_on(std::ostream* progress, int rank) {
    progress_ = progress;
    rank_ = rank;
    std::vector<ColumnCycle> done = cached();
    std::vector<double> state;
    while (done.size() < nodes_.size() && (done.empty() || done.back().sustained())) {
      if (!done.empty() && state.empty()) {
        const auto s = parse_state(read_text_file(file(done.back().lambda, "_state.txt")), unknowns());
        if (!s) {  // its state is lost: that step is done again
          done.pop_back();
          continue;
        }
        state = *s;
      }
      const auto started = std::chrono::steady_clock::now();
      ColumnCycle c = done.empty() ? first_step(state) : next_step(done, state);
      if (c.sustained()) write_file_atomically(file(c.lambda, "_state.txt"), state_text(state));
      write_file_atomically(file(c.lambda, ".csv"), file_text(c, plan_.column_periods, grid_));
      report(progress, rank, c, std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
      done.push_back(c);
    }
    for (ColumnCycle& c : done)
      if (wants_floquet(c) && !c.floquet_done) measure_floquet(c, progress, rank);
  }

  // The settled steps at the scan's own λ: their points take the multiplier.
  bool wants_floquet(const ColumnCycle& c) const {
    return c.sustained() && c.run.converged && std::find(plan_.lambda.begin(), plan_.lambda.end(), c.lambda) != plan_.lambda.end();
  }

  // The return map run from the state the step ended in, at the step's own tolerances and step budget; a run that
  // fails leaves the reason in the multiplier's note (and no multiplier).
  void measure_floquet(ColumnCycle& c, std::ostream* progress, int rank) const {
    const auto s = parse_state(read_text_file(file(c.lambda, "_state.txt")), unknowns());
    ReturnMapOptions options;
    options.rtol = search_rtol;
    options.tolerance = {.atol = c.atol, .atol_floor = c.atol_floor, .atol_mass = c.atol_mass};
    // The budget the step itself ran under where that was larger (a step walked at a larger column_steps and
    // taken under a smaller one: far below the curve a period costs more CVODE steps than a small budget allows).
    options.max_steps = long(std::max(plan_.column_step_budget(), c.step_budget));
    try {
      if (!s) throw std::runtime_error("the state the step ended in is not readable");
      c.floquet = return_map_multiplier(point_model(plan_, a_, c.lambda, plan_.size()), *s, {c.run.period, c.m0_min, c.m0_max, c.spread}, options);
    } catch (const std::exception& e) {
      c.floquet = {};
      c.floquet.note = std::string("no multiplier: ") + e.what();
    }
    c.floquet_done = true;
    write_file_atomically(file(c.lambda, "_floquet.csv"), floquet_text(c));
    if (progress)
      *progress << "aggkit scan: [rank " << rank << "] cycle column a = " << shortest_text(a_) << ", lambda = " << short_number(c.lambda)
                << ": largest Floquet multiplier " << (c.floquet.bounded ? "<= " : "") << short_number(c.floquet.multiplier) << " ("
                << c.floquet.note << ", " << short_number(c.floquet.seconds) << " s)\n" << std::flush;
  }

  std::filesystem::path file(double lambda, const std::string& suffix) const {
    return points_ / ("cycle_column_a" + shortest_text(a_) + "_lambda" + shortest_text(lambda) + "_N" +
                      std::to_string(plan_.size()) + suffix);
  }
  std::size_t unknowns() const { return point_model(plan_, a_, branch_anchor, plan_.size()).unknowns(); }

  // On the Hopf normal form's cycle at 0.95 λ_crit: ln(1e3)/(2 Re μ), the time its radial rate needs to take the
  // amplitude's error down by 1e3, and 16 periods.
  ColumnCycle first_step(std::vector<double>& state) const {
    const double lambda = nodes_.front();
    const AggregationModel model = point_model(plan_, a_, lambda, plan_.size());
    SteadyBranch steady(point_model(plan_, a_, branch_anchor, plan_.size()), branch_anchor);
    const BranchSteadyState s = steady.at(lambda);
    ColumnCycle c = blank(lambda, std::nan(""));
    if (!s.steady.converged) {
      c.note = "no steady state at the column's start: " + s.note;
      return c;
    }
    try {
      const HopfNormalForm form = hopf_normal_form(model, s.steady.n);
      const double period = 2.0 * M_PI / form.mu.imag();
      if (!(form.mu.real() > 0.0) || !(period > 0.0)) {
        c.note = "the steady state at the column's start is not an unstable focus (mu = " + shortest_text(form.mu.real()) +
                 " + " + shortest_text(form.mu.imag()) + "i)";
        return c;
      }
      std::vector<double> from = form.cycle_point(s.steady.n);
      // The normal form's point keeps the steady state's mass to first order only (shifted_density takes a
      // decrease as n exp(shift / n)): scaled back onto the model's mass, so that a relaxation from it is not read
      // as a run that gained mass (a = 1 at 0.95 λ_crit on a fixed-pivot K = 8, r = 1.6 grid: +0.74 %).
      const double scale = shell_mass_ / total_mass(from, model.pivots());
      for (double& v : from) v *= scale;
      double relaxation = std::log(1e3) / (2.0 * form.mu.real()), cycle_period = period;
      if (relaxation > extrapolate_beyond * period) {
        double level = 0.0;  // the section through the steady state, which the normal form's cycle circles
        for (double v : s.steady.n) level += v;
        try {
          const CycleExtrapolation e = extrapolate_cycle(model, from, level, period, extrapolation_options());
          c.note = "started by extrapolating the return map: " + e.note;
          if (e.jump <= extrapolation_taken) {
            from = e.state;
            cycle_period = e.period;
            relaxation = 0.0;
          }
        } catch (const std::exception& e) {  // the relaxation from the normal form's point instead
          c.note = std::string("the return map's extrapolation failed: ") + e.what();
        }
      }
      return run(model, from, cycle_period, relaxation + 16.0 * cycle_period, c, state, 0);
    } catch (const std::exception& e) {
      c.note = std::string("no start on the normal form's cycle: ") + e.what();
      return c;
    }
  }

  // The returns' extrapolation at the first level's tolerances, each round within the column's step budget.
  CycleExtrapolationOptions extrapolation_options() const {
    CycleExtrapolationOptions o;
    o.rtol = search_rtol;
    o.run = column_tolerances.front().run();
    o.max_steps = long(plan_.column_step_budget());
    o.tolerance = 1e-5;
    o.max_rounds = 8;
    o.on_round = [this](const CycleExtrapolation& e) {
      if (progress_)
        *progress_ << "aggkit scan: [rank " << rank_ << "] cycle column a = " << shortest_text(a_) << ": extrapolating the return map, round "
                   << e.rounds << ": jump " << short_number(e.jump) << ", period " << short_number(e.period) << " (" << e.returns
                   << " returns, " << short_number(e.seconds) << " s)\n" << std::flush;
    };
    return o;
  }

  // From the state the cycle above ended in, `periods` predicted periods: T extrapolated in ln T against ln λ from
  // the two cycles above (the slope kept within [-2, -1/2]), or ∝ 1/λ from one.
  ColumnCycle next_step(const std::vector<ColumnCycle>& done, std::vector<double>& state) const {
    const double lambda = nodes_[done.size()];
    const ColumnCycle& above = done.back();
    double slope = -1.0;
    if (done.size() >= 2) {
      const ColumnCycle& before = done[done.size() - 2];
      slope = std::clamp(std::log(above.run.period / before.run.period) / std::log(above.lambda / before.lambda), -2.0, -0.5);
    }
    const double period = above.run.period * std::pow(lambda / above.lambda, slope);
    ColumnCycle c = blank(lambda, above.lambda);
    return run(point_model(plan_, a_, lambda, plan_.size()), state, period, double(plan_.column_periods) * period, c, state,
               level_of(above));
  }

  // The first of column_tolerances that the step's run took (0 for a step cached before the levels).
  static std::size_t level_of(const ColumnCycle& step) {
    for (std::size_t i = 0; i < column_tolerances.size(); ++i)
      if (step.atol == column_tolerances[i].atol && step.atol_floor == column_tolerances[i].floor &&
          step.atol_mass == column_tolerances[i].mass)
        return i;
    return 0;
  }

  // What a step that outgrew the grid (ColumnCycle::outgrew_grid) says of it ("" for any other).
  static std::string outgrown_text(const ColumnCycle& c, std::size_t N) {
    if (!c.outgrew_grid()) return "";
    return ": the cycle outgrows the grid (its clusters reach N = " + std::to_string(N) + ": " +
           grid_end_text(c.top_octave_mass, c.leaked_mass) + ")";
  }

  // For a run that stopped early: what it saw of the grid's end where that is beyond ColumnCycle::grid_end_limit
  // ("" else). Not a verdict: the run did not show whether the cycle goes on.
  std::string grid_end_seen(const GridEnd& seen, std::size_t N) const {
    const double top = seen.top_octave_mass / shell_mass_, leaked = seen.leaked_mass / shell_mass_;
    if (std::max(top, leaked) <= ColumnCycle::grid_end_limit) return "";
    return " (by then, on N = " + std::to_string(N) + ", " + grid_end_text(top, leaked) + ")";
  }

  ColumnCycle blank(double lambda, double from_lambda) const {
    ColumnCycle c;
    c.a = a_;
    c.lambda = lambda;
    c.from_lambda = from_lambda;
    return c;
  }

  // The run from `from` to `end` at each of column_tolerances from `first_level` on, until one settles on a cycle
  // (run_at_level); the walk stops where none does, with each level's reason.
  ColumnCycle run(const AggregationModel& model, std::vector<double> from, double period, double end, ColumnCycle c,
                  std::vector<double>& state, std::size_t first_level) const {
    // The start's far tail holds densities ~1e-20 below zero (the graded grid's shares undershoot at the steep
    // front): set to zero, a change far below every density's absolute tolerance, so that a run never starts
    // outside the positive cone.
    for (double& n : from) n = std::max(n, 0.0);
    const std::vector<double> pivots = grid_pivots(model.grid, model.size);
    std::string reasons;
    ColumnCycle tried;
    for (std::size_t level = first_level; level < column_tolerances.size(); ++level) {
      tried = run_at_level(model, from, period, end, c, state, column_tolerances[level], pivots);
      if (tried.sustained()) return tried;
      reasons += (reasons.empty() ? "" : "; ") + column_tolerances[level].text() + ": " + tried.note;
      if (tried.outgrew_grid()) break;  // finer tolerances do not make the grid longer
      if (tried.out_of_steps) {  // a finer floor takes more steps (8 of the 10 stops of the scan from scratch ran out at both)
        if (level + 1 < column_tolerances.size()) reasons += "; the finer floors not run: they take more steps still";
        break;
      }
    }
    tried.note = "the column stops here: " + reasons;  // the record of the finest level's run
    return tried;
  }

  // The run at one level of tolerances, its second half classified; `state` becomes the state at its last upward M0
  // crossing (the next step's start) where it settled. A second half that is not yet a sustained oscillation,
  // settled or unsettled (the envelope still settling from the cycle above: its amplitude shrinking by a few
  // percent over the tail reads as damped, while the unstable steady state it would decay to repels at Re μ),
  // is run on from that crossing for twice `end`, up to 2 times: near the curve the cycle attracts weakly
  // (largest nontrivial Floquet multiplier 0.8 at a = 0.8, λ = 3.2e-3), and a second half of 12 or more
  // periods tells a modulation that persists from one that decays (cycle_settling needs 10). A run whose mass
  // grows beyond mass_gain_limit is not taken. c.note says why where it did not settle.
  ColumnCycle run_at_level(const AggregationModel& model, std::vector<double> from, double period, double end, ColumnCycle c,
                           std::vector<double>& state, const ColumnTolerance& tolerance, const std::vector<double>& pivots) const {
    constexpr int extensions = 2;
    c.atol = tolerance.atol;
    c.atol_floor = tolerance.floor;
    c.atol_mass = tolerance.mass;
    c.step_budget = plan_.column_step_budget();
    c.run_end = 0;
    c.leaked_mass = c.top_octave_mass = 0.0;
    for (int attempt = 0; attempt <= extensions; ++attempt) {
      const double length = attempt == 0 ? end : 2.0 * end;
      std::optional<CycleStart> start;
      GridEnd grid_end;
      try {
        start = cycle_start_from_run(model, length, period / outputs_per_period, search_rtol, from, long(plan_.column_step_budget()),
                                     tolerance.run(), &grid_end);
      } catch (const StepLimitReached& e) {
        c.run_end += length;
        c.note = "the run to t = " + shortest_text(length) + " needs more than column_steps = " + std::to_string(plan_.column_step_budget()) +
                 " steps (" + e.what() + ")" + grid_end_seen(grid_end, model.size);
        c.leaked_mass = c.top_octave_mass = std::nan("");  // the run was cut short: no verdict on the grid's end
        c.out_of_steps = true;
        return c;
      } catch (const std::exception& e) {
        c.note = std::string("the run failed: ") + e.what() + grid_end_seen(grid_end, model.size);
        c.leaked_mass = c.top_octave_mass = std::nan("");
        return c;
      }
      c.run_end += length;
      c.leaked_mass = std::max(c.leaked_mass, grid_end.leaked_mass / shell_mass_);
      c.top_octave_mass = std::max(c.top_octave_mass, grid_end.top_octave_mass / shell_mass_);
      if (!start) {
        c.classified = false;
        c.mass_change = std::nan("");
        c.note = "the run to t = " + shortest_text(length) + " does not oscillate" + outgrown_text(c, model.size);
        return c;
      }
      classify(*start, c);
      c.mass_change = total_mass(start->state, pivots) / shell_mass_ - 1.0;
      if (c.mass_change > mass_gain_limit) {
        c.classified = false;
        c.note = "the mass grew by " + short_number(c.mass_change) + " beyond the model's over the run (more than " + shortest_text(mass_gain_limit) +
                 "; aggregation, shattering and drop truncation never add mass: densities below their tolerance)";
        return c;
      }
      if (c.sustained()) {
        state = start->state;
        return c;
      }
      from = start->state;
      period = start->period;
    }
    // Not sustained after every run, so not settled either (a settled run is sustained and returned above).
    std::string why = " (not converged";
    if (c.settling == CycleSettling::settling) {
      why += ": its last four periods spread by " + short_number(c.spread);
      if (!std::isnan(c.contraction)) why += ", modulation contracting by " + short_number(c.contraction) + " a period";
    }
    c.note = "after runs to t = " + shortest_text(c.run_end) + " in all the last second half is " + to_string(c.run.regime) + why + ")" +
             outgrown_text(c, model.size);
    return c;
  }

  // The run's second half: classified like a point's run (amplitude, mean, decay rate), and its periods from
  // the upward crossings of M0's mid-range (analysis/crossing_periods.hpp): settled where its last four agree
  // to 2e-3 and M0's largest value over the last two to 5e-3 (with 1 % and 2 %, a = 0.8, λ = 3.2e-3 on the scan
  // grid was taken while its amplitude still grew from the cycle above: period 127.0 against the shot 128.33),
  // or unsettled where over 10 or more periods their modulation persists. The steady state being unstable, a
  // settled or unsettled bounded oscillation is sustained.
  void classify(const CycleStart& start, ColumnCycle& c) const {
    OscillationCriteria criteria = plan_.criteria;
    criteria.tail_fraction = 1.0;  // the series is the run's second half already
    OscillationClassification& k = c.run;
    k = classify_oscillation(start.times, start.m0, criteria);
    c.classified = true;
    // At the internal steps: far below the curve a burst is narrower than the outputs' spacing.
    const CrossingPeriods crossings = crossing_periods(start.step_times, start.step_m0);
    c.m0_min = crossings.lowest;
    c.m0_max = crossings.highest;
    const CycleSettlingVerdict verdict = cycle_settling(crossings, start.step_times, start.step_m0);
    c.settling = verdict.settling;
    c.spread = verdict.spread;
    c.contraction = verdict.contraction;
    k.converged = false;
    if (verdict.settling == CycleSettling::too_few_crossings) return;
    // The crossings' verdict replaces the classifier's (and its note, which counted turning points).
    k.regime = Regime::sustained;
    k.period = verdict.period;
    k.cycles = verdict.periods;
    k.converged = verdict.settling == CycleSettling::settled;
    k.note.clear();
  }

  void report(std::ostream* progress, int rank, const ColumnCycle& c, double seconds) const {
    if (!progress) return;
    char line[256];
    std::snprintf(line, sizeof line, "aggkit scan: [rank %d] cycle column a = %s, lambda = %s: ", rank,
                  shortest_text(a_).c_str(), short_number(c.lambda).c_str());
    *progress << line
              << (c.sustained() ? "sustained, " + std::string(c.run.converged ? "" : "unsettled (periods vary by " + short_number(c.spread) + "), mean ") +
                                    "period " + short_number(c.run.period) + ", M0 " + short_number(c.m0_min) + " .. " + short_number(c.m0_max)
                              : c.note)
              << " (run to t = " << short_number(c.run_end) << ", " << short_number(seconds) << " s)\n" << std::flush;
  }

  const ScanPlan& plan_;
  std::filesystem::path points_;
  double a_;
  std::string grid_;
  // The model's initial mass, on which the integrator holds Σ x_k n_k + L (the run's own leak L starting at 0):
  // a start that lost mass to drop truncation in the runs before gets it back, and the cycles live on that mass
  // shell as the shooting's do (solvers/limit_cycle.cpp). A run's gain is measured against it: against the
  // start's mass, a = 0.85, λ = 1.78e-5 "gained" 0.19 % at every floor (from 0.99825 to 1.0000002 one period
  // later, then 1.0003) and the column stopped there.
  double shell_mass_ = 0;
  std::vector<double> nodes_;  // the first cycle's λ, then the plan's λ below it, descending
  std::ostream* progress_ = nullptr;  // the walk's progress lines (walk_on)
  int rank_ = 0;
};

}  // namespace

std::string short_number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return text;
}

std::string grid_end_text(double top_octave_mass, double leaked_mass) {
  return "its top octave held up to " + short_number(top_octave_mass) + " of the mass and " + short_number(leaked_mass) + " left through N";
}

CycleColumns follow_cycle_columns(const ScanPlan& plan, const std::filesystem::path& points,
                                  const std::vector<LambdaCritRow>& crit, std::ostream* progress, const SerialTask* beside) {
  CycleColumns result;
  if (plan.column_periods == 0) return result;
  std::vector<Column> columns;
  for (const LambdaCritRow& row : crit)
    if (row.criticality == "supercritical" && row.lambda_crit_model_grid > 0.0)
      columns.emplace_back(plan, points, row.a, row.lambda_crit_model_grid);
  const MpiWorld world = mpi_world();
  // The ranks draw the runs in this order: the longest first, so that they finish together (the deeper a column,
  // the more steps and the dearer each: the walk's λ nodes, then a, larger first; from scratch the a = 1 column,
  // drawn last in order of a, ran alone for 280 s of the 1601). The Hopf curve beside them, about as long as a
  // column, is drawn third.
  std::vector<std::size_t> order(columns.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](std::size_t l, std::size_t r) {
    return columns[l].nodes() != columns[r].nodes() ? columns[l].nodes() > columns[r].nodes() : columns[l].a() > columns[r].a();
  });
  constexpr std::size_t curve_task = std::size_t(-1);
  if (beside) order.insert(order.begin() + std::ptrdiff_t(std::min<std::size_t>(2, order.size())), curve_task);
  compute_unfinished_runs(
      order.size(),
      [&](std::size_t i) { return order[i] == curve_task ? beside->finished() : columns[order[i]].finished(); },
      [&](std::size_t i, std::size_t, std::size_t) {
        return order[i] == curve_task ? beside->compute() : columns[order[i]].walk(progress, world.rank);
      },
      "aggkit scan",
      "the attracting cycles continued down " + std::to_string(columns.size()) + " columns of lambda" +
          (beside ? ", and the converged Hopf curve" : ""),
      progress);
  for (const Column& column : columns)
    for (const ColumnCycle& c : column.cached()) result[{c.a, c.lambda}] = c;
  return result;
}

}  // namespace aggkit

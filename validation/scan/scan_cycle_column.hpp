#pragma once
// The attracting cycle followed down each a's column of λ below the Hopf point, with the flow as the corrector:
// natural-parameter continuation of the periodic orbit in λ [Kuznetsov2004, Sec. 10.2], each step a CVODE run
// of a few predicted periods started on the cycle of the λ above. Far below the curve the cycles are relaxation
// oscillations whose periods grow ~1/λ (a = 1: 20.9 at 0.95 λ_crit, 837 at λ = 3.2e-4); the growth away from
// the unstable steady state takes 24/Re μ, beyond any affordable run there, and a shooting solve with its
// Floquet multipliers costs tens of period maps at rtol 1e-10. Started on the cycle above, the run needs only
// the few periods in which the attracting cycle pulls it in (nontrivial Floquet multipliers 0.1–0.8 per period
// where shot), and its second half, classified like a point's run, is the evidence: a sustained oscillation
// that neither grows nor decays, with its period and M0 range.
//
// The walk per a: the first run starts on the Hopf normal form's cycle at 0.95 λ_crit (λ_crit and the form on
// the scan's own grid, solvers/hopf_normal_form.hpp), for ln(1e3)/(2 Re μ) + 16 periods; then each of the
// scan's λ below it, in descending order and with geometric steps between them of at most a factor 10^(1/2),
// runs `periods` predicted periods (the period extrapolated in ln T against ln λ from the two cycles above, or
// ∝ 1/λ from one) from the state the run above ended in, run on (up to 2 times, for twice as long) until its
// periods have settled on one cycle or show a modulation that persists (a quasi-periodic or period-k
// oscillation, or a cycle attracting with |μ| ≥ 0.9: analysis/crossing_periods.hpp). Each step runs with the
// monomers' absolute tolerance 1e-16 (the quiescent phase far below the curve holds n_1 ~ 1e-10) and no class's
// tolerance worth more than 1e-15 of the mass, or 1e-18 where that does not settle, from the level
// of the step above on (scan_cycle_column.cpp, column_tolerances). The walk stops at the first λ where no floor's run shows a sustained
// oscillation, settled or unsettled, without gaining mass, within column_steps CVODE steps a run; the λ below it get
// no column cycle. Each settled step at one of the scan's λ then gets its largest nontrivial Floquet multiplier
// from the return map (solvers/cycle_return_map.hpp: a perturbation of the state the step ended in, run on at
// the step's tolerances for the few returns it takes to fall to the floor, which the step's own period spread
// raises): the point's floquet_max and cycle_stable, an upper bound where the attraction is beyond the floor.
// A column's results depend only on the plan and a,
// never on the ranks: columns are spread over the MPI ranks, each walked by one, and every step is cached in
// DIR/points/cycle_column_* (the record and the state it ended in), so an interrupted scan resumes mid-column.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <map>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "analysis/crossing_periods.hpp"
#include "analysis/oscillation.hpp"
#include "solvers/cycle_return_map.hpp"
#include "validation/scan/scan_output.hpp"
#include "validation/runs/run_store.hpp"
#include "validation/scan/scan_plan.hpp"
#include "validation/scan/scan_record.hpp"

namespace aggkit {

struct ColumnCycle {
  static constexpr double nan = ScanRecord::nan;
  double a = 0, lambda = 0;
  bool classified = false;                    // the run's second half was classified (else the run failed)
  // Its classification: amplitude, mean and decay rate from classify_oscillation; regime, period, cycles and
  // converged from the crossings (Column::classify).
  OscillationClassification run;
  // How the periods between M0's upward mid-range crossings settled (analysis/crossing_periods.hpp): settled on
  // one cycle (run.converged), or unsettled, a modulation that persists (quasi-periodic, period-k or a cycle
  // attracting with |μ| ≥ 0.9), its relative spread and per-period contraction given. Both are sustained.
  CycleSettling settling = CycleSettling::too_few_crossings;
  double spread = nan, contraction = nan;
  bool sustained() const {
    return classified && run.regime == Regime::sustained && (run.converged || settling == CycleSettling::unsettled);
  }
  double m0_min = nan, m0_max = nan;          // over the run's second half
  double run_end = nan;                       // the run's length
  double from_lambda = nan;                   // the λ of the cycle it started on
  // The absolute tolerances its run took (the last level tried where none settled): atol_k = atol / k^3 within
  // [atol_floor, atol_mass · M / x_k] (0: no upper bound), relative to the unit monodisperse start.
  double atol = nan, atol_floor = nan, atol_mass = nan;
  std::size_t step_budget = 0;                // the most CVODE steps a run of it could take (0: not recorded)
  double mass_change = nan;                   // the mass Σ x_i N_i the run ended on, relative to the model's initial mass, - 1
                                              // (< 0: drop truncation's loss)
  // What its runs showed of the grid's end, relative to the model's initial mass (NaN: cached before it was
  // watched): the most mass lost through N by the end of a run, and the most held at an output by the classes
  // above N/2 (solvers/limit_cycle.hpp GridEnd).
  double leaked_mass = nan, top_octave_mass = nan;
  // The largest relative gain of the mass over a run that is taken (scan_cycle_column.cpp: aggregation,
  // shattering and drop truncation never add mass, so a gain is the integrator's error alone).
  static constexpr double mass_gain_limit = 1e-3;
  // A step that stopped the column for its dynamics (no oscillation, or one that does not settle; not the step
  // budget, a failed run or a mass gain, whose runs leave these NaN or are told by the gain) while the grid's end
  // held, or had lost through N, more of the mass than the runs' relative tolerance (so the dynamics', not the
  // integrator's round-off): the cycle continued from the λ above outgrows N. Far below the curve the quiescent
  // phase grows clusters to ever larger sizes (the period ~1/λ); once they reach the last classes the truncated
  // equations leak mass every burst, so their runs drift instead of settling, or stop bursting (brownian a = 1 on
  // the coarse grid cut at N = 2^14, λ = 2.2e-3: 4 % of the mass gone in 12 periods, the periods spread by 5e-3 and
  // drifting; on the shipped grid, N = 2^40, λ = 3.16e-9, the cycle still settles with 4e-4 gone).
  static constexpr double grid_end_limit = 1e-6;
  bool outgrew_grid() const {
    return !sustained() && !(mass_change > mass_gain_limit) && !std::isnan(top_octave_mass) && !std::isnan(leaked_mass) &&
           std::max(top_octave_mass, leaked_mass) > grid_end_limit;
  }
  // Its run stopped at the step budget (while it is computed; not stored): a finer floor needs more steps still.
  bool out_of_steps = false;
  std::string note;                           // why the walk stopped here, or how a first step started ("" else)
  // The largest nontrivial Floquet multiplier of a settled step on the scan's grid, from the return map
  // (solvers/cycle_return_map.hpp) run from the state the step ended in at its own tolerances: `floquet.found()`
  // where measured (an upper bound where `floquet.bounded`); its note says why not otherwise.
  ReturnMapMultiplier floquet;
  bool floquet_done = false;                  // measured or tried (cached in DIR/points/cycle_column_*_floquet.csv)
};

// (a, λ) -> the column's cycle there.
using CycleColumns = std::map<std::pair<double, double>, ColumnCycle>;

// Walks (or reads back) the column of every a whose crossing on the scan's grid is supercritical
// (crit's lambda_crit_model_grid and criticality, from add_hopf_criticality), over the plan's λ below
// 0.95 λ_crit, with runs of plan.column_periods predicted periods. Called on every rank; every rank returns the
// same columns. `beside`, if given, is drawn first and run by one rank beside the columns.
CycleColumns follow_cycle_columns(const ScanPlan& plan, const std::filesystem::path& points,
                                  const std::vector<LambdaCritRow>& crit, std::ostream* progress,
                                  const SerialTask* beside = nullptr);

// A point whose steady state is unstable and that has no attracting cycle of its own (verdict "unstable": its
// search found none, or it sought none because the column reached it, ScanPoint::column_period) takes the
// column's sustained run as its run: regime, period, amplitude and run_end from it, the verdict then
// sustained, and a note saying where the run started. Other points are left as they are. Returns whether r changed.
bool adopt_column_cycle(const ColumnCycle& c, std::size_t periods, ScanRecord& r);

// A number in the columns' notes and progress lines: 6 significant digits.
std::string short_number(double x);
// What a run saw of the grid's end, as the notes say it (fractions of the mass; ColumnCycle's leaked_mass and
// top_octave_mass): "its top octave held up to … of the mass and … left through N".
std::string grid_end_text(double top_octave_mass, double leaked_mass);

// adopt_column_cycle for every record from its column; an "unstable" point at or below the λ where its column
// stopped gets the column's reason in its note. A point whose steady state is stable (damped or steady) where its
// column's cycle settled at the same λ is bistable: two attractors, the steady state by its spectrum and the cycle
// by its settled run (brownian a = 0.6 between the Hopf points 4.88e-9 and 9.80e-10 below λ_crit = 5.72e-8, a
// stable focus beside a relaxation cycle of period 8.2e7 at λ = 3.16e-9); the cycle's period and M0 range go to
// cycle_period, cycle_m0_min and cycle_m0_max, its multiplier to floquet_max. A sustained point whose own run
// confirmed the column's cycle takes the column's multiplier.
void adopt_column_cycles(const CycleColumns& columns, std::size_t periods, std::vector<ScanRecord>& records);

}  // namespace aggkit

// How the scan's points take what their columns found (validation/scan/scan_cycle_column.hpp): the sustained run
// where the steady state is unstable, the multiplier where the point's own run confirmed the cycle, and
// bistability where the steady state is stable and the column's cycle settled at the same λ.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "analysis/text.hpp"
#include "validation/scan/scan_cycle_column.hpp"

namespace aggkit {

// The column step's multiplier into r (floquet_max, cycle_stable), and the words the note gives it ("" where the
// step has none: not measured).
static std::string adopt_column_floquet(const ColumnCycle& c, ScanRecord& r) {
  if (c.floquet_done && c.floquet.found()) {
    r.floquet_max = c.floquet.multiplier;
    r.cycle_stable = c.floquet.multiplier < 1.0 ? "yes" : "no";
    return "largest nontrivial Floquet multiplier from the return map " +
           (c.floquet.bounded ? "<= " + short_number(c.floquet.multiplier) + " (an upper bound: "
                              : short_number(c.floquet.multiplier) +
                                    (std::isnan(c.floquet.multiplier_error) ? std::string() : " +- " + short_number(c.floquet.multiplier_error)) + " (") +
           c.floquet.note + ")";
  }
  return c.floquet_done ? "no Floquet multiplier: " + c.floquet.note : std::string();
}

// A stable steady state (r's verdict damped or steady) beside the column's settled cycle at the same λ.
static void adopt_bistable(const ColumnCycle& c, ScanRecord& r) {
  if (!c.sustained() || !c.run.converged) return;
  const std::string stable = r.verdict == "damped" ? "a stable focus" : "a stable node";
  r.verdict = "bistable";
  r.cycle_period = c.run.period;
  r.cycle_m0_min = c.m0_min;
  r.cycle_m0_max = c.m0_max;
  const std::string floquet = adopt_column_floquet(c, r);
  r.note = "bistable: the steady state is " + stable + " (Re mu = " + short_number(r.rightmost_real) +
           ") and the cycle continued down the column from lambda = " + shortest_text(c.from_lambda) + " attracts here too (settled: period " +
           short_number(c.run.period) + ", M0 " + short_number(c.m0_min) + " .. " + short_number(c.m0_max) + (floquet.empty() ? "" : "; " + floquet) +
           ")" + (r.note.empty() ? "" : "; " + r.note);
}

// An unstable point at or below the column's step whose cycle outgrew the grid: the truncated equations' attractor
// there is not the cycle of the equations the grid stands for. Below that step the cycles are longer still (the
// period ~1/λ down every column) and their quiescent phase grows larger clusters, so they outgrow N too.
static void adopt_outgrown_grid(const ColumnCycle& c, ScanRecord& r) {
  r.verdict = "not-representable";
  r.note = "not representable on this grid: the cycle continued down the column outgrows N at lambda = " + shortest_text(c.lambda) +
           (c.lambda == r.lambda ? "" : " (the cycles below it are longer still)") + " (" + c.note + "); a larger N would be needed" +
           (r.note.empty() ? "" : "; " + r.note);
}

void adopt_column_cycles(const CycleColumns& columns, std::size_t periods, std::vector<ScanRecord>& records) {
  for (ScanRecord& r : records) {
    // A point whose own run confirmed the cycle that the column reached (it sought none of its own): the column's
    // multiplier is that cycle's.
    if (r.verdict == "sustained" && std::isnan(r.floquet_max))
      if (const auto c = columns.find({r.a, r.lambda}); c != columns.end() && c->second.sustained())
        if (const std::string floquet = adopt_column_floquet(c->second, r); !floquet.empty())
          r.note += (r.note.empty() ? "" : "; ") + ("the column's cycle: " + floquet);
    if (r.verdict == "damped" || r.verdict == "steady")
      if (const auto c = columns.find({r.a, r.lambda}); c != columns.end()) adopt_bistable(c->second, r);
    if (r.verdict != "unstable") continue;
    if (const auto c = columns.find({r.a, r.lambda}); c != columns.end() && adopt_column_cycle(c->second, periods, r))
      continue;
    // Where the column stopped above this λ (or at it): say where and why.
    for (const auto& [key, c] : columns)
      if (key.first == r.a && !c.sustained() && c.lambda >= r.lambda) {
        if (c.outgrew_grid()) {
          adopt_outgrown_grid(c, r);
          break;
        }
        r.note = "no cycle from the column either: at lambda = " + shortest_text(c.lambda) + " " + c.note +
                 (r.note.empty() ? "" : "; " + r.note);
        break;
      }
  }
}

bool adopt_column_cycle(const ColumnCycle& c, std::size_t periods, ScanRecord& r) {
  if (r.verdict != "unstable" || !c.sustained()) return false;
  record_run(c.run, c.run_end, r);
  r.verdict = "sustained";
  r.agree = "yes";
  const std::string unsettled =
      c.settling == CycleSettling::unsettled
          ? "; not periodic: its " + std::to_string(c.run.cycles) + " periods between M0's crossings vary by " + short_number(c.spread) +
                " of their mean " + short_number(c.run.period) + " without settling (modulation contracting by " + short_number(c.contraction) +
                " a period: quasi-periodic or period-k, or a cycle attracting with |mu| >= 0.9)"
          : "";
  std::string floquet = adopt_column_floquet(c, r);
  if (!floquet.empty()) floquet = "; " + floquet;
  // A settled cycle whose run nonetheless put mass into the grid's end: N begins to matter here.
  if (std::max(c.top_octave_mass, c.leaked_mass) > ColumnCycle::grid_end_limit)
    floquet += "; the cycle reaches the grid's end (" + grid_end_text(c.top_octave_mass, c.leaked_mass) + " over the run): its figures depend on N";
  r.note = "sustained on the " + std::string(c.run.converged ? "cycle" : "oscillation") + " continued down the column: the run is " +
           std::to_string(periods) + " predicted periods from the cycle at lambda = " + shortest_text(c.from_lambda) +
           " (its second half classified; M0 " + shortest_text(c.m0_min) + " .. " + shortest_text(c.m0_max) + "; atol_k = " +
           shortest_text(c.atol) + " / k^3 at least " + shortest_text(c.atol_floor) +
           (c.atol_mass > 0.0 ? " and at most " + shortest_text(c.atol_mass) + " M / x_k" : std::string()) + ")" + unsettled + floquet + (r.note.empty() ? "" : "; " + r.note);
  return true;
}

}  // namespace aggkit

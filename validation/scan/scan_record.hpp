#pragma once
// One scan point's result: a row of DIR/scan.csv, and the file DIR/points/<index>.csv that marks the
// point finished (so an interrupted scan resumes without recomputing it).
#include <cstddef>
#include <limits>
#include <optional>
#include <string>

#include "analysis/oscillation.hpp"

namespace aggkit {

struct ScanRecord {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  std::size_t index = 0;
  double a = 0, lambda = 0;
  std::size_t size = 0;                // truncation N of the run
  // The time-series classification of the scan's moment (analysis/oscillation.hpp).
  std::string regime;                  // steady | damped | sustained (irregular: no verdict)
  double period = nan, amplitude = nan, mean = nan;
  double decay_rate = nan, decay_rate_error = nan;
  std::size_t cycles = 0;
  bool converged = false;
  // Linear stability of the steady state (empty where not computed).
  std::string regime_stability;        // steady | damped | sustained, from the rightmost eigenvalue
  double rightmost_real = nan, rightmost_imag = nan;
  std::string agree;                   // yes | no | "" (no stability verdict)
  std::string note;                    // commas and line breaks replaced
  // The classified moment at the steady state (NaN where none was found): a relaxing run must end near it.
  double mean_steady = nan;
  // The verdict of the same point on the refined grid over twice the run ([scan] refine; "" where not
  // repeated): a damped or steady verdict stands only if the repeat relaxes too.
  std::string regime_refined;
  // How the point's steady state was reached (solvers/steady_branch.hpp): "newton from a CVODE start",
  // "continuation from lambda = ... in K Newton solves", or where and why the continuation stopped.
  std::string steady_how;
  // yes: the rightmost eigenvalues (rightmost_real, rightmost_imag) converged; no: the eigensolver failed
  // (the note says how); "": no steady state to analyse.
  std::string spectrum_converged;
  // The verdict from the evidence of the steady state and its spectrum, with the time series (regime) as the
  // confirmation: damped (stable focus), steady (stable node), sustained (unstable steady state and a
  // sustained time series), unstable (unstable steady state; the run did not show the cycle: no periodic
  // orbit computed), bistable (a stable steady state, and the cycle continued down its column attracts at the same
  // λ: cycle_period, cycle_m0_min and cycle_m0_max are that cycle's), no-positive-steady-state (the
  // continuation's roots went negative above this λ: see steady_how), not-representable (unstable, and the cycle
  // continued down its column outgrew the grid here or above: its run stopped oscillating with its mass at N),
  // unresolved (no steady state reached, or no converged spectrum).
  std::string verdict;
  // The attracting cycle around an unstable steady state, computed by shooting (solvers/limit_cycle.hpp; NaN and
  // "" where none was computed or found): its period, M0's range over it, the largest nontrivial Floquet
  // multiplier |μ| and whether the cycle is stable (every nontrivial |μ| < 1).
  double cycle_period = nan, cycle_m0_min = nan, cycle_m0_max = nan, floquet_max = nan;
  std::string cycle_stable;
  // The time the point's run reached: the scene's [time] end, or the confirmation's length sized by the
  // spectrum ([scan] confirm_run); NaN where it was not run.
  double run_end = nan;
  // Not in scan.csv (so that it is reproducible): where and how long.
  double seconds = 0;
  int rank = 0;
};

// A run's classification into r's run columns (regime .. converged, run_end = end; its note first).
void record_run(const OscillationClassification& c, double end, ScanRecord& r);

// A relaxing verdict: damped or steady.
inline bool is_relaxing(const ScanRecord& r) { return r.regime == "damped" || r.regime == "steady"; }

// The outcome in words for a progress line: the regime and only the numbers it has, e.g. "sustained, period
// 52.1, amplitude 0.0123", "damped, decay rate 0.0042 (period 48.7)", "steady" (never "period nan").
std::string outcome_summary(const ScanRecord& record);

// The header and a row of scan.csv (full precision: a resumed scan writes the same bytes).
std::string scan_csv_header();
std::string scan_csv_row(const ScanRecord& record);
// The point file: the scan.csv header and row plus `seconds,rank`.
std::string point_file_text(const ScanRecord& record);
// Reads a point file's text back; std::nullopt if it is not a complete point file of this format.
std::optional<ScanRecord> parse_point_file(const std::string& text);

}  // namespace aggkit

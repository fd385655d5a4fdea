#pragma once
// The files a scan writes (scan.hpp), each atomically: scan.csv, lambda_crit.csv, truncation_check.csv,
// timing.csv, and the phase diagram drawn by validation/scan/plot_scan.py.
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "validation/scan/scan_record.hpp"

namespace aggkit {

// One row of lambda_crit.csv.
struct LambdaCritRow {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  double a = 0;
  double lambda_crit = nan, error = nan;  // error: bound on |λ_crit - true crossing| at this N
  std::string method;                     // "grid" (bracket of the scan's time-series verdicts) or "hopf"
  double lambda_sustained = nan, lambda_relaxing = nan;  // the grid bracket
  double period = nan;                    // 2π/ω at the Hopf point (method hopf)
  std::size_t size = 0;                   // N
  double lambda_crit_2N = nan, change_2N = nan;  // the truncation check, if asked
  std::string note;
  // λ_crit converged on a graded grid (method hopf-converged): for the converged curve, lambda_crit_2N and
  // change_2N hold the N/2 -> N step of its doubling (N the column `N`); K and r of the grid, and the
  // values with K doubled and with r - 1 halved with their relative changes; converged: all three changes
  // within the curve's tolerance (1 %).
  std::size_t resolved = 0;
  double ratio = nan;
  double lambda_crit_2K = nan, change_2K = nan, lambda_crit_half_ratio = nan, change_half_ratio = nan;
  std::string converged;  // "yes", "no" or "" (not a converged curve)
  // The Hopf bifurcation's criticality (validation/scan/scan_criticality.hpp): the first Lyapunov coefficient
  // 5 % below the crossing on the scan's own grid (eigenvector norm 1), "supercritical" or "subcritical", and the M0
  // half-range of the cycle the normal form predicts there.
  double lambda_crit_model_grid = nan;  // the crossing on the scan's own model grid
  double lyapunov = nan;
  std::string criticality;
  double m0_half_range = nan;
};

// One row of truncation_check.csv: a point at N and at 2N.
struct TruncationCheckRow {
  ScanRecord at_N, at_2N;
};

void write_scan_csv(const std::filesystem::path& file, const std::vector<ScanRecord>& records);
void write_timing_csv(const std::filesystem::path& file, const std::vector<ScanRecord>& records);
void write_lambda_crit_csv(const std::filesystem::path& file, const std::vector<LambdaCritRow>& rows);
void write_truncation_check_csv(const std::filesystem::path& file, const std::vector<TruncationCheckRow>& rows);

// Draws the phase diagram `png` and the bifurcation diagrams `bifurcation_png` (M0 of the steady states and of the
// cycles against λ, per a) from scan.csv and lambda_crit.csv with plot_scan.py; returns "" or why it failed
// (plotting is a convenience, never fatal).
std::string plot_phase_diagram(const std::filesystem::path& scan_csv, const std::filesystem::path& lambda_crit_csv,
                               const std::filesystem::path& png, const std::filesystem::path& bifurcation_png,
                               const std::string& title, bool log_lambda);

}  // namespace aggkit

#pragma once
// `aggkit scan SCENE --out DIR`: every (a, λ) point of a scan scene (scan_plan.hpp) is integrated and
// classified; points are spread over the MPI ranks; each finished point is kept in DIR/points/ so that an
// interrupted scan resumes without recomputing it. Outputs (rank 0, each written atomically):
//   DIR/scan.csv             one row per point: a,lambda,regime,period,amplitude,... (scan_record.hpp)
//   DIR/lambda_crit.csv      a,lambda_crit,... λ_crit(a) (scan_output.hpp)
//   DIR/truncation_check.csv the points repeated at 2N (if the scene asks)
//   DIR/timing.csv           wall time and rank of each point (not in scan.csv, which is reproducible)
//   DIR/phase_diagram.png    regimes over (a, λ) with the λ_crit(a) curve
#include <cstddef>
#include <filesystem>
#include <ostream>

#include "validation/scan/scan_plan.hpp"

namespace aggkit {

struct ScanOptions {
  std::filesystem::path out;
  bool plot = true;
  std::ostream* progress = nullptr;  // progress lines (each rank its own points); nullptr: quiet
};

struct ScanOutcome {
  std::size_t points = 0;    // grid points
  std::size_t reused = 0;    // results found finished in DIR/points (over all tasks, this rank's view)
  std::size_t computed = 0;  // runs this rank made
  std::size_t failed = 0;    // runs that failed (all ranks); rerunning retries them
  int exit_code = 0;         // 0 complete, 1 some runs failed
};

// Throws InputError for an unusable output folder (key "--out").
ScanOutcome run_scan(const ScanPlan& plan, const ScanOptions& options);

}  // namespace aggkit

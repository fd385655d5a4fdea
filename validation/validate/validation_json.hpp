#pragma once
// DIR/validation.json: the machine-readable record of `aggkit validate`:
//   { "aggkit_version", "tier", "jobs", "wall_seconds" (this invocation), "pass", "exit_code",
//     "counts": { scenes, pass, fail, bad_input, error, not_run, resumed }, "notes": [ scenes left out ],
//     "scenes": [ { name, folder, file, kind (run | scan), tier, engines, result (pass | FAIL | bad input |
//                   error | not run), exit_code, signal?, resumed, wall_seconds, problem?, scan_points?,
//                   worst: { engine, reference, observable, kind, max_relative_error, time, tolerance,
//                            tolerance_stderr?, max_error_in_stderr?, tolerance_used, pass } | null,
//                   comparisons, failed_comparisons, summary (its summary.json, relative to DIR), log,
//                   images: [ PNG files relative to DIR ] } ] }
// Numbers that are not finite are written as null.
#include <cstddef>
#include <string>
#include <vector>

#include "validation/validate/scene_outcome.hpp"

namespace aggkit {

struct ValidationTotals {
  SceneTier tier = SceneTier::fast;
  std::size_t jobs = 1;
  double wall_seconds = 0;
  int exit_code = 0;
  std::vector<std::string> notes;
};

std::string validation_json(const std::vector<SceneOutcome>& scenes, const ValidationTotals& totals);

}  // namespace aggkit

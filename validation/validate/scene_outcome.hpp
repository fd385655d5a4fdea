#pragma once
// What one scene of a validation gave: its verdict, and for the table and the report what its outputs say —
// DIR/<folder>/summary.json of a run scene (engines, comparisons), DIR/<folder>/scan.csv and lambda_crit.csv
// of a scan scene, the plots under DIR/<folder>/ and the end of its log DIR/logs/<folder>.log.
#include <cstddef>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "validation/validate/validation_plan.hpp"

namespace aggkit {

// unchecked: the scene ran to completion (exit 0) but nothing in it was checked against a tolerance — a run
// scene without a comparison that has one, or a scan scene — so it neither passes nor fails.
enum class Verdict { pass, fail, bad_input, error, not_run, unchecked };
// "pass", "FAIL", "bad input", "error", "not run", "ran (no check)"
const char* to_string(Verdict verdict);
// The key of a verdict in validation.json's counts: pass, fail, bad_input, error, not_run, no_check.
const char* count_key(Verdict verdict);
// A scene that ran and was checked or ran without a check: what a validation without failures holds.
bool without_failure(Verdict verdict);

struct ComparisonLine {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  std::string engine, reference, observable, kind;  // kind: series | final
  double error = nan;                // largest relative error
  double time = nan;                 // where (series)
  std::optional<double> tolerance;   // relative part
  std::optional<double> tolerance_stderr;  // k of `stderr = k`
  double error_in_stderr = nan;      // largest |x - x_ref| / σ
  double tolerance_used = nan;       // largest |x - x_ref| / allowed (<= 1 passes)
  std::optional<bool> pass;          // none: reported only
  std::string note;
};

struct EngineLine {
  std::string label, name, status;   // status: completed | failed
  double wall_seconds = ComparisonLine::nan;
  std::string error;
};

struct SceneOutcome {
  PlannedScene scene;
  Verdict verdict = Verdict::not_run;
  bool resumed = false;          // finished in an earlier `aggkit validate` into the same DIR, not rerun
  int exit_code = -1;            // of its `aggkit run` / `aggkit scan`; -1: none (signal, not started)
  int signal = 0;
  double wall_seconds = ComparisonLine::nan;
  std::vector<EngineLine> engines;
  std::vector<ComparisonLine> comparisons;
  std::optional<std::size_t> worst;  // the comparison nearest to (or furthest past) its tolerance
  std::size_t scan_points = 0;       // scan scenes: rows of scan.csv
  std::vector<std::string> images;   // PNG files under DIR/<folder>/, relative to DIR (report.png first)
  std::string problem;               // one line: why it did not pass
  std::string log_tail;              // the last lines of its log, when it did not pass
};

// The worst comparison: a failed one before a passing one, then the largest share of its tolerance used
// (a NaN error counts as the largest); comparisons without a tolerance only if no comparison has one, then
// by their error. None without comparisons.
std::optional<std::size_t> worst_comparison(const std::vector<ComparisonLine>& comparisons);

// Reads the outcome of a scene whose child process ended with `exit_code` (-1 with `signal`, or not started).
SceneOutcome read_scene_outcome(const std::filesystem::path& out, const PlannedScene& scene, int exit_code, int signal,
                                double wall_seconds, bool resumed);

}  // namespace aggkit

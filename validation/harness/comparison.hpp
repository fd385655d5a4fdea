#pragma once
// Comparison of engines against the reference engine of a scene: for each observable of the series, the
// largest relative error |x - x_ref| / |x_ref| over the output times (absolute error where x_ref = 0,
// analysis/moments.hpp) and the time where it occurs, checked against the tolerance if one is given. When
// either engine ran an ensemble, also the largest error in combined standard errors σ = sqrt(σ² + σ_ref²);
// a tolerance with `stderr = k` allows |x - x_ref| <= relative |x_ref| + k σ at each output time.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "validation/harness/engine_record.hpp"

namespace aggkit {

struct ComparisonResult {
  std::string engine;                // label
  std::string reference;             // label
  std::string observable;
  bool final_state = false;          // a value of observe.final (final.json), not a series
  double max_relative_error = 0.0;   // NaN if an engine failed or produced NaN
  double time = 0.0;                 // where the maximum occurs (NaN if undefined)
  std::optional<double> tolerance;   // none: reported only (relative part of the tolerance)
  std::optional<double> stderr_multiple;  // k of a `stderr = k` tolerance
  double max_standard_errors = std::numeric_limits<double>::quiet_NaN();  // max |x - x_ref| / σ; NaN without σ
  // The largest share of the allowed error used, max |x - x_ref| / (relative |x_ref| + k σ) over the output
  // times: <= 1 passes; NaN without a tolerance or a number.
  double tolerance_used = std::numeric_limits<double>::quiet_NaN();
  bool pass = true;                  // error <= tolerance (a NaN error fails); true without tolerance
  std::string note;                  // why there is no number, if there is none
};

// First, for every engine, one result per final value with a stated value (compare.final { value = v }).
// Then one result per non-reference engine and series observable, in scene order; then, for engines that report
// final states (particle engines) when the reference does too, one per number of observe.final: the
// relative error of the final.json means, against `final` tolerances, with σ the combined standard errors.
std::vector<ComparisonResult> compare_engines(const ComparisonPlan& plan, const Observation& observe,
                                              const std::vector<EngineRecord>& records);

}  // namespace aggkit

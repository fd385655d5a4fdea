#pragma once
// Comparison of engines against the reference engine of a scene: for each observable of the series, the
// largest relative error |x - x_ref| / |x_ref| over the output times (absolute error where x_ref = 0,
// analysis/moments.hpp) and the time where it occurs, checked against the tolerance if one is given.
#include <optional>
#include <string>
#include <vector>

#include "validation/engine_record.hpp"

namespace aggkit {

struct ComparisonResult {
  std::string engine;                // label
  std::string reference;             // label
  std::string observable;
  double max_relative_error = 0.0;   // NaN if an engine failed or produced NaN
  double time = 0.0;                 // where the maximum occurs (NaN if undefined)
  std::optional<double> tolerance;   // none: reported only
  bool pass = true;                  // error <= tolerance (a NaN error fails); true without tolerance
  std::string note;                  // why there is no number, if there is none
};

// One result per non-reference engine and series observable, in scene order.
std::vector<ComparisonResult> compare_engines(const ComparisonPlan& plan, const Observation& observe,
                                              const std::vector<EngineRecord>& records);

}  // namespace aggkit

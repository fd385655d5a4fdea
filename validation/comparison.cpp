#include "validation/comparison.hpp"

#include <cmath>
#include <limits>

#include "analysis/moments.hpp"
#include "validation/text.hpp"

namespace aggkit {

namespace {

constexpr double not_a_number = std::numeric_limits<double>::quiet_NaN();

// Max over the output times of the relative error of column j; the first NaN wins (it is the worst).
void largest_error(const EngineRecord& engine, const EngineRecord& reference, std::size_t j, ComparisonResult& result) {
  result.max_relative_error = -1.0;
  for (std::size_t i = 0; i < engine.times.size(); ++i) {
    const double error = relative_error(engine.values[i][j], reference.values[i][j]);
    if (std::isnan(error)) {
      result.max_relative_error = not_a_number;
      result.time = engine.times[i];
      result.note = "not a number at t = " + shortest_text(engine.times[i]);
      return;
    }
    if (error > result.max_relative_error) {
      result.max_relative_error = error;
      result.time = engine.times[i];
    }
  }
}

}  // namespace

std::vector<ComparisonResult> compare_engines(const ComparisonPlan& plan, const Observation& observe,
                                              const std::vector<EngineRecord>& records) {
  const EngineRecord* reference = nullptr;
  for (const auto& record : records)
    if (record.label == plan.reference) reference = &record;
  std::vector<ComparisonResult> results;
  for (const auto& record : records) {
    if (&record == reference) continue;
    for (std::size_t j = 0; j < observe.series.size(); ++j) {
      ComparisonResult result;
      result.engine = record.label;
      result.reference = plan.reference;
      result.observable = observe.series[j].name();
      if (const Tolerance* tolerance = plan.tolerance_for(result.observable)) result.tolerance = tolerance->relative_error;
      if (!reference || !reference->completed() || !record.completed() || record.times.size() != reference->times.size() ||
          record.times.empty()) {
        result.max_relative_error = result.time = not_a_number;
        result.note = !reference || !reference->completed() ? "reference engine did not complete"
                                                            : "engine did not complete";
      } else {
        largest_error(record, *reference, j, result);
      }
      // A NaN error fails any tolerance.
      result.pass = !result.tolerance || result.max_relative_error <= *result.tolerance;
      results.push_back(std::move(result));
    }
  }
  return results;
}

}  // namespace aggkit

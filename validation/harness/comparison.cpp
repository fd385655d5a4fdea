#include "validation/harness/comparison.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "analysis/moments.hpp"
#include "validation/io/text.hpp"

namespace aggkit {

namespace {

constexpr double not_a_number = std::numeric_limits<double>::quiet_NaN();

std::string three_digits(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2e", x);
  return text;
}

double standard_error(const EngineRecord& record, std::size_t i, std::size_t j) {
  return record.standard_errors.empty() ? 0.0 : record.standard_errors[i][j];
}

// Max over the output times of the relative error of column j (the first NaN wins: it is the worst), the
// largest error in combined standard errors, and whether every time is within `tolerance`.
void largest_error(const EngineRecord& engine, const EngineRecord& reference, std::size_t j, const Tolerance* tolerance,
                   ComparisonResult& result) {
  result.max_relative_error = -1.0;
  const bool ensemble = !engine.standard_errors.empty() || !reference.standard_errors.empty();
  if (ensemble) result.max_standard_errors = 0.0;
  for (std::size_t i = 0; i < engine.times.size(); ++i) {
    const double x = engine.values[i][j], x_ref = reference.values[i][j];
    const double sigma = std::hypot(standard_error(engine, i, j), standard_error(reference, i, j));
    if (ensemble) result.max_standard_errors = std::max(result.max_standard_errors, std::abs(x - x_ref) / sigma);
    if (tolerance) {
      const double allowed = tolerance->relative_error * (x_ref != 0.0 ? std::abs(x_ref) : 1.0) +
                             tolerance->standard_errors.value_or(0.0) * sigma;
      if (!(std::abs(x - x_ref) <= allowed)) result.pass = false;
      const double used = x == x_ref ? 0.0 : std::abs(x - x_ref) / allowed;  // NaN: set below
      result.tolerance_used = i == 0 ? used : std::max(result.tolerance_used, used);
    }
    const double error = relative_error(x, x_ref);
    if (std::isnan(error)) {
      result.max_relative_error = not_a_number;
      if (tolerance) result.tolerance_used = not_a_number;
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

const FinalStatistic* find_final(const EngineRecord& record, const std::string& name) {
  for (const auto& f : record.finals)
    if (f.name == name) return &f;
  return nullptr;
}

// The final-state comparison of one observable: the same rule as a series at one time.
ComparisonResult compare_final(const EngineRecord& engine, const EngineRecord& reference, const std::string& name,
                               const Tolerance* tolerance) {
  ComparisonResult result;
  result.engine = engine.label;
  result.reference = reference.label;
  result.observable = name;
  result.final_state = true;
  result.time = not_a_number;
  if (tolerance) {
    result.tolerance = tolerance->relative_error;
    result.stderr_multiple = tolerance->standard_errors;
  }
  const FinalStatistic* x = find_final(engine, name);
  const FinalStatistic* ref = find_final(reference, name);
  if (!x || !ref) {
    result.max_relative_error = not_a_number;
    result.note = "no final value";
    result.pass = !tolerance;
    return result;
  }
  const double sigma = std::hypot(x->standard_error, ref->standard_error);
  if (sigma > 0) result.max_standard_errors = std::abs(x->mean - ref->mean) / sigma;
  result.max_relative_error = relative_error(x->mean, ref->mean);
  if (tolerance) {
    const double allowed = tolerance->relative_error * (ref->mean != 0.0 ? std::abs(ref->mean) : 1.0) +
                           tolerance->standard_errors.value_or(0.0) * sigma;
    result.pass = std::abs(x->mean - ref->mean) <= allowed;
    result.tolerance_used = x->mean == ref->mean ? 0.0 : std::abs(x->mean - ref->mean) / allowed;
  }
  return result;
}

// A final value against a stated constant v (compare.final { value = v, ... }): the same rule with the
// constant in place of the reference and σ the engine's own standard error.
ComparisonResult compare_final_value(const EngineRecord& engine, const Tolerance& tolerance) {
  ComparisonResult result;
  result.engine = engine.label;
  result.reference = "stated value";
  result.observable = tolerance.observable;
  result.final_state = true;
  result.time = not_a_number;
  result.tolerance = tolerance.relative_error;
  result.stderr_multiple = tolerance.standard_errors;
  const double value = *tolerance.value;
  result.note = "stated value " + shortest_text(value);
  const FinalStatistic* x = engine.completed() ? find_final(engine, tolerance.observable) : nullptr;
  if (!x) {
    result.max_relative_error = not_a_number;
    result.note += engine.completed() ? "; the engine reports no final value of this name" : "; engine did not complete";
    result.pass = false;
    return result;
  }
  if (x->standard_error > 0) result.max_standard_errors = std::abs(x->mean - value) / x->standard_error;
  result.max_relative_error = relative_error(x->mean, value);
  const double allowed = tolerance.relative_error * (value != 0.0 ? std::abs(value) : 1.0) +
                         tolerance.standard_errors.value_or(0.0) * x->standard_error;
  result.pass = std::abs(x->mean - value) <= allowed;  // a NaN mean fails
  result.tolerance_used = x->mean == value ? 0.0 : std::abs(x->mean - value) / allowed;
  result.note += ", engine " + shortest_text(x->mean) + (x->standard_error > 0 ? " ± " + shortest_text(x->standard_error) : "");
  return result;
}

// The size distributions at the distribution times (compare.distribution): E = ||n - n_ref||_2 over the
// sizes of either, σ² = Σ_k σ_k² from the engine's realizations (σ_k² their sample variance of n_k over R),
// and the mean single-realization error, the figure of [Kalinov2022, Table 1].
ComparisonResult compare_distributions(const EngineRecord& engine, const EngineRecord& reference, const Tolerance& tolerance) {
  ComparisonResult result;
  result.engine = engine.label;
  result.reference = reference.label;
  result.observable = "distribution";
  result.tolerance = tolerance.relative_error;
  result.stderr_multiple = tolerance.standard_errors;
  result.max_relative_error = -1.0;
  result.max_standard_errors = not_a_number;
  const auto distance = [](const std::vector<double>& a, const std::vector<double>& b) {
    double sum = 0;
    for (std::size_t k = 0; k < std::max(a.size(), b.size()); ++k) {
      const double d = (k < a.size() ? a[k] : 0.0) - (k < b.size() ? b[k] : 0.0);
      sum += d * d;
    }
    return std::sqrt(sum);
  };
  std::string errors, single;
  for (std::size_t d = 0; d < engine.distributions.size() && d < reference.distributions.size(); ++d) {
    const DistributionRecord& x = engine.distributions[d];
    const DistributionRecord& ref = reference.distributions[d];
    const double error = distance(x.n, ref.n), norm = distance(ref.n, {});
    double variance = 0, per_run = 0;
    const std::size_t runs = x.realizations.size();
    for (std::size_t k = 0; k < x.n.size() && runs > 1; ++k) {
      double squares = 0;
      for (const auto& r : x.realizations) squares += (r[k] - x.n[k]) * (r[k] - x.n[k]);
      variance += squares / double(runs - 1) / double(runs);
    }
    for (const auto& r : x.realizations) per_run += distance(r, ref.n) / double(runs);
    const double sigma = std::sqrt(variance);
    if (sigma > 0) result.max_standard_errors = std::max(std::isnan(result.max_standard_errors) ? 0.0 : result.max_standard_errors, error / sigma);
    const double allowed = tolerance.relative_error * norm + tolerance.standard_errors.value_or(0.0) * sigma;
    if (!(error <= allowed)) result.pass = false;
    const double used = error == 0.0 ? 0.0 : error / allowed;
    result.tolerance_used = d == 0 ? used : std::max(result.tolerance_used, used);
    const double relative = norm > 0 ? error / norm : error;
    if (!(relative <= result.max_relative_error)) {
      result.max_relative_error = relative;
      result.time = x.t;
    }
    errors += (errors.empty() ? "" : ", ") + shortest_text(x.t) + ": " + three_digits(error);
    if (runs > 1) single += (single.empty() ? "" : ", ") + shortest_text(x.t) + ": " + three_digits(per_run);
  }
  if (result.max_relative_error < 0) {
    result.max_relative_error = result.time = not_a_number;
    result.pass = false;
    result.note = "no distributions to compare";
    return result;
  }
  result.note = "||n - n_ref||_2 at t = " + errors;
  if (!single.empty()) result.note += "; mean of single realizations: " + single;
  return result;
}

}  // namespace

std::vector<ComparisonResult> compare_engines(const ComparisonPlan& plan, const Observation& observe,
                                              const std::vector<EngineRecord>& records) {
  const EngineRecord* reference = nullptr;
  for (const auto& record : records)
    if (record.label == plan.reference) reference = &record;
  std::vector<ComparisonResult> results;
  for (const auto& record : records) {
    // Final values against stated values: every engine, the reference too.
    for (const Tolerance& t : plan.final_tolerances)
      if (t.value) results.push_back(compare_final_value(record, t));
    if (&record == reference || plan.reference.empty()) continue;
    for (std::size_t j = 0; j < observe.series.size(); ++j) {
      ComparisonResult result;
      result.engine = record.label;
      result.reference = plan.reference;
      result.observable = observe.series[j].name();
      const Tolerance* tolerance = plan.tolerance_for(result.observable);
      if (tolerance) {
        result.tolerance = tolerance->relative_error;
        result.stderr_multiple = tolerance->standard_errors;
      }
      if (!reference || !reference->completed() || !record.completed() || record.times.size() != reference->times.size() ||
          record.times.empty()) {
        result.max_relative_error = result.time = not_a_number;
        result.note = !reference || !reference->completed() ? "reference engine did not complete"
                                                            : "engine did not complete";
      } else {
        largest_error(record, *reference, j, tolerance, result);
      }
      // A NaN error fails any tolerance; largest_error checked every time against the tolerance.
      if (result.tolerance && !(result.max_relative_error >= 0.0)) result.pass = false;
      results.push_back(std::move(result));
    }
    if (plan.distribution && reference && record.completed() && reference->completed())
      results.push_back(compare_distributions(record, *reference, *plan.distribution));
    if (!reference || !record.completed() || !reference->completed() || record.finals.empty() || reference->finals.empty())
      continue;
    for (const std::string& name : observe.final_state) {
      const Tolerance* tolerance = plan.final_tolerance_for(name);
      if (!Observable::from_name(name)->is_profile() && !(tolerance && tolerance->value))
        results.push_back(compare_final(record, *reference, name, tolerance));
    }
  }
  // A final tolerance that no pair of engines could be checked against fails: it was asked for.
  for (const Tolerance& t : plan.final_tolerances) {
    if (t.value) continue;  // checked on every engine above
    bool checked = false;
    for (const auto& r : results) checked = checked || (r.final_state && r.observable == t.observable);
    if (!checked) {
      ComparisonResult missing;
      missing.reference = plan.reference;
      missing.observable = t.observable;
      missing.final_state = true;
      missing.tolerance = t.relative_error;
      missing.stderr_multiple = t.standard_errors;
      missing.max_relative_error = missing.time = not_a_number;
      missing.pass = false;
      missing.note = "no engine and reference with final states to compare";
      results.push_back(missing);
    }
  }
  return results;
}

}  // namespace aggkit

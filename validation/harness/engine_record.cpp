#include "validation/harness/engine_record.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "validation/io/text.hpp"

namespace aggkit {

Measurement measure_state(const Scene& scene, double t, const ObservedState& state) {
  Measurement m;
  m.values.reserve(scene.observe.series.size());
  for (const auto& observable : scene.observe.series) m.values.push_back(observable.value(state));
  m.leaked_mass = state.leaked_mass();
  for (double wanted : scene.observe.distribution_times)
    if (std::abs(t - wanted) <= 1e-9 * scene.time.end) {
      m.distribution = state.distribution();
      m.sizes = state.sizes();
    }
  return m;
}

void record_measurements(EngineRecord& record, const Scene& scene, double t, const std::vector<Measurement>& realizations) {
  const std::vector<double>& outputs = scene.time.outputs;
  const std::size_t index = record.times.size();
  if (index >= outputs.size() || !(std::abs(t - outputs[index]) <= 1e-9 * scene.time.end))
    throw std::runtime_error("engine " + record.label + " reported t = " + shortest_text(t) + ", expected " +
                             (index < outputs.size() ? "t = " + shortest_text(outputs[index]) : "no more outputs"));
  if (realizations.empty()) throw std::runtime_error("engine " + record.label + " reported no realization");
  const double output_time = outputs[index];
  const std::size_t runs = realizations.size(), columns = scene.observe.series.size();
  std::vector<double> mean(columns, 0.0);
  for (const Measurement& m : realizations)
    for (std::size_t j = 0; j < columns; ++j) mean[j] += m.values[j];
  for (double& x : mean) x /= double(runs);
  if (runs > 1) {
    std::vector<double> errors;
    for (std::size_t j = 0; j < columns; ++j) {
      double squares = 0.0;
      for (const Measurement& m : realizations) squares += (m.values[j] - mean[j]) * (m.values[j] - mean[j]);
      errors.push_back(std::sqrt(squares / double(runs - 1) / double(runs)));
    }
    record.standard_errors.push_back(std::move(errors));
  }
  if (scene.observe.has_series_measures()) {
    record.realization_values.resize(std::max(record.realization_values.size(), runs));
    for (std::size_t r = 0; r < runs; ++r) record.realization_values[r].push_back(realizations[r].values);
  }
  record.times.push_back(output_time);
  record.values.push_back(std::move(mean));
  double leaked = 0;
  for (const Measurement& m : realizations) leaked += m.leaked_mass;
  record.final_mass_leak = leaked / double(runs);
  if (!realizations.front().distribution.empty()) {
    std::size_t longest = 0;
    for (const Measurement& m : realizations) longest = std::max(longest, m.distribution.size());
    std::vector<double> n(longest, 0.0);
    for (const Measurement& m : realizations)
      for (std::size_t k = 0; k < m.distribution.size(); ++k) n[k] += m.distribution[k];
    for (double& x : n) x /= double(runs);
    std::vector<std::vector<double>> each;
    if (runs > 1)
      for (const Measurement& m : realizations) each.push_back(m.distribution);
    record.distributions.push_back({output_time, std::move(n), std::move(each), realizations.front().sizes});
  }
}

void record_series_measures(EngineRecord& record, const Scene& scene) {
  const Observation& observe = scene.observe;
  const double slack = 1e-9 * scene.time.end;
  std::vector<double> t;
  std::size_t first = record.times.size();
  for (std::size_t i = 0; i < record.times.size(); ++i)
    if (record.times[i] >= observe.window_start - slack && record.times[i] <= observe.window_end + slack) {
      first = std::min(first, i);
      t.push_back(record.times[i]);
    }
  for (const std::string& name : observe.final_state) {
    const Observable observable = *Observable::from_name(name);
    if (!observable.is_series_measure()) continue;
    std::size_t j = 0;
    while (observe.series[j].name() != observable.source()) ++j;  // the scene checked that it is there
    std::vector<double> values;
    for (const auto& series : record.realization_values) {
      std::vector<double> x;
      for (std::size_t i = first; i < first + t.size() && i < series.size(); ++i) x.push_back(series[i][j]);
      values.push_back(x.size() == t.size() ? observable.measure(t, x) : std::numeric_limits<double>::quiet_NaN());
    }
    FinalStatistic statistic{name, std::numeric_limits<double>::quiet_NaN(), 0.0};
    if (!values.empty()) {
      double sum = 0;
      for (double v : values) sum += v;
      statistic.mean = sum / double(values.size());
      if (values.size() > 1) {
        double squares = 0;
        for (double v : values) squares += (v - statistic.mean) * (v - statistic.mean);
        statistic.standard_error = std::sqrt(squares / double(values.size() - 1) / double(values.size()));
      }
    }
    record.finals.push_back(statistic);
  }
}

}  // namespace aggkit

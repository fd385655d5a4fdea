#include "validation/harness/engine_record.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "validation/io/text.hpp"

namespace aggkit {

Measurement measure_state(const Scene& scene, double t, const ObservedState& state) {
  Measurement m;
  m.values.reserve(scene.observe.series.size());
  for (const auto& observable : scene.observe.series) m.values.push_back(observable.value(state));
  m.leaked_mass = state.leaked_mass();
  for (double wanted : scene.observe.distribution_times)
    if (std::abs(t - wanted) <= 1e-9 * scene.time.end) m.distribution = state.distribution();
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
    record.distributions.push_back({output_time, std::move(n)});
  }
}

}  // namespace aggkit

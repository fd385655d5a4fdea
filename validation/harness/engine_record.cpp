#include "validation/harness/engine_record.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "validation/io/text.hpp"

namespace aggkit {

void record_state(EngineRecord& record, const Scene& scene, double t, const SystemState& state) {
  const std::vector<double>& outputs = scene.time.outputs;
  const std::size_t index = record.times.size();
  if (index >= outputs.size() || !(std::abs(t - outputs[index]) <= 1e-9 * scene.time.end))
    throw std::runtime_error("engine " + record.label + " reported t = " + shortest_text(t) + ", expected " +
                             (index < outputs.size() ? "t = " + shortest_text(outputs[index]) : "no more outputs"));
  const double output_time = outputs[index];
  std::vector<double> row;
  row.reserve(scene.observe.series.size());
  for (const auto& observable : scene.observe.series) row.push_back(observable.evaluate(state));
  const std::size_t runs = state.realisations();
  if (runs > 1) {
    std::vector<double> errors;
    for (std::size_t j = 0; j < scene.observe.series.size(); ++j) {
      double squares = 0.0;
      for (std::size_t r = 0; r < runs; ++r) {
        const double deviation = scene.observe.series[j].evaluate(state.realisation(r)) - row[j];
        squares += deviation * deviation;
      }
      errors.push_back(std::sqrt(squares / double(runs - 1) / double(runs)));
    }
    record.standard_errors.push_back(std::move(errors));
  }
  record.times.push_back(output_time);
  record.values.push_back(std::move(row));
  record.final_mass_leak = state.leaked_mass();
  const auto& wanted = scene.observe.distribution_times;
  if (std::find(wanted.begin(), wanted.end(), output_time) != wanted.end())
    record.distributions.push_back({output_time, state.distribution()});
}

}  // namespace aggkit

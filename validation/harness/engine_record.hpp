#pragma once
// What one engine produced in a run: the requested series and distributions, its statistics and timing.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "validation/engines/engine.hpp"
#include "validation/scene/scene.hpp"

namespace aggkit {

struct DistributionRecord {
  double t;
  std::vector<double> n;  // n_1..n_N, the mean over the realizations
  std::vector<std::vector<double>> realizations;  // each realization's n_1..n_N, with more than one
  std::vector<double> sizes;  // a graded grid's pivots (n then holds the numbers at them); empty: 1..N
};

struct EngineRecord {
  std::string label;
  std::string name;
  std::string description;
  std::vector<double> times;                  // output times reached, in order
  std::vector<std::vector<double>> values;    // values[i][j]: observe.series[j] at times[i]
  // standard_errors[i][j]: standard error of values[i][j] over an ensemble (stochastic engines with more than
  // one realisation); empty otherwise.
  std::vector<std::vector<double>> standard_errors;
  std::vector<DistributionRecord> distributions;
  // The series of each realization, realization_values[r][i][j] as values[i][j]; kept only when observe.final
  // has series measures, which are taken of them.
  std::vector<std::vector<std::vector<double>>> realization_values;
  std::vector<FinalStatistic> finals;         // final.json of a particle engine, then the series measures
  EngineStatistics statistics;
  double wall_seconds = 0.0;
  double final_mass_leak = std::numeric_limits<double>::quiet_NaN();
  std::optional<std::string> failure;  // why the run failed, if it did
  std::vector<std::string> warnings;   // what the engine warned about (EngineObserver::warning)
  bool completed() const { return !failure; }
};

// The scene's series observables on one state at output time t (and its distribution at a distribution time).
Measurement measure_state(const Scene& scene, double t, const ObservedState& state);

// Appends the measurements of the realizations at time `t`, which must be the next output time of the scene
// (std::runtime_error otherwise): their mean, and with more than one realization the standard error of each
// observable (the sample standard deviation over the realizations divided by sqrt(realizations)); keeps the
// mean distribution at a distribution time.
void record_measurements(EngineRecord& record, const Scene& scene, double t, const std::vector<Measurement>& realizations);

// Appends to record.finals each series measure of observe.final (oscillation_period:M0, ...): taken of each
// realization's series over observe.window, their mean and standard error (0 for one realization).
void record_series_measures(EngineRecord& record, const Scene& scene);

}  // namespace aggkit

#pragma once
// What one engine produced in a run: the requested series and distributions, its statistics and timing.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "validation/engine.hpp"
#include "validation/scene.hpp"

namespace aggkit {

struct DistributionRecord {
  double t;
  std::vector<double> n;  // n_1..n_N
};

struct EngineRecord {
  std::string label;
  std::string name;
  std::string description;
  std::vector<double> times;                  // output times reached, in order
  std::vector<std::vector<double>> values;    // values[i][j]: observe.series[j] at times[i]
  std::vector<DistributionRecord> distributions;
  EngineStatistics statistics;
  double wall_seconds = 0.0;
  double final_mass_leak = std::numeric_limits<double>::quiet_NaN();
  std::optional<std::string> failure;  // why the run failed, if it did
  bool completed() const { return !failure; }
};

// Appends the observables of `state`, reported by the engine at time `t`, which must be the next output
// time of the scene (std::runtime_error otherwise); keeps the distribution at a distribution time.
void record_state(EngineRecord& record, const Scene& scene, double t, const SystemState& state);

}  // namespace aggkit

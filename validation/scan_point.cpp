#include "validation/scan_point.hpp"

#include <chrono>
#include <vector>

#include "validation/system_state.hpp"

namespace aggkit {

ScanRecord run_scan_point(const ScanPlan& plan, const ScanPoint& point, std::size_t size,
                          const std::function<void(double t)>& progress) {
  const auto started = std::chrono::steady_clock::now();
  Scene run;  // the point's scene: the scan scene's model with this (a, λ, N) and its time grid
  run.name = plan.scene.name;
  run.model = point_model(plan, point.a, point.lambda, size);
  run.time = plan.scene.time;

  std::vector<double> times, values;
  times.reserve(run.time.outputs.size());
  values.reserve(run.time.outputs.size());
  EngineObserver observer;
  observer.output = [&](double t, const SystemState& state) {
    times.push_back(t);
    values.push_back(state.moment(plan.series_order));
  };
  observer.progress = progress;
  plan.scene.engines.front()->run(run, observer);

  const OscillationClassification c = classify_oscillation(times, values, plan.criteria);
  ScanRecord r;
  r.index = point.index;
  r.a = point.a;
  r.lambda = point.lambda;
  r.size = size;
  r.regime = to_string(c.regime);
  r.period = c.period;
  r.amplitude = c.amplitude;
  r.mean = c.mean;
  r.decay_rate = c.decay_rate;
  r.decay_rate_error = c.decay_rate_error;
  r.cycles = c.cycles;
  r.converged = c.converged;
  r.note = c.note;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return r;
}

}  // namespace aggkit

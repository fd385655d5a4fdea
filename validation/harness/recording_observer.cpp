#include "validation/harness/recording_observer.hpp"

#include <utility>

namespace aggkit {

EngineObserver recording_observer(const Scene& scene, EngineRecord& record, std::mutex& lock, ObserverSinks sinks) {
  EngineObserver observer;
  observer.measure = [&scene](double t, const ObservedState& state) { return measure_state(scene, t, state); };
  observer.record = [&scene, &record, &lock, reached = sinks.reached](double t, std::vector<Measurement> realizations) {
    {
      std::lock_guard guard(lock);
      record_measurements(record, scene, t, realizations);
    }
    if (reached) reached(t);
  };
  observer.final_state = [&record, &lock](std::vector<FinalStatistic> values) {
    std::lock_guard guard(lock);
    record.finals = std::move(values);
  };
  observer.progress = [reached = sinks.reached](double t) {
    if (reached) reached(t);
  };
  observer.status = [note = std::move(sinks.note)](const std::string& what) {
    if (note) note(what);
  };
  observer.warning = [&record, &lock](const std::string& what) {
    std::lock_guard guard(lock);
    record.warnings.push_back(what);
  };
  return observer;
}

}  // namespace aggkit

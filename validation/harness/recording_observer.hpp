#pragma once
// The observer that keeps an engine's run in an EngineRecord: one for `aggkit run` (harness.cpp) and for
// Python (python/run_binding.cpp), so that both record the same measurements, final values and warnings.
#include <functional>
#include <mutex>
#include <string>

#include "validation/engines/engine.hpp"
#include "validation/harness/engine_record.hpp"
#include "validation/scene/scene.hpp"

namespace aggkit {

// Where the observer's reports of progress go besides the record.
struct ObserverSinks {
  std::function<void(double t)> reached;           // the time reached (after each recorded output too)
  std::function<void(const std::string& what)> note;  // a stage or count in words
};

// An observer measuring the scene's observables on the engine's states and keeping in `record` the
// measurements at each output time, the final values and the warnings, under `lock` (an engine may report
// from several threads; a checkpoint copies the record under the same lock). `scene`, `record` and `lock`
// must outlive the observer. The caller adds what is its own: folder, checkpoint, ranks, final configuration.
EngineObserver recording_observer(const Scene& scene, EngineRecord& record, std::mutex& lock, ObserverSinks sinks);

}  // namespace aggkit

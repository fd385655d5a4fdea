#pragma once
// Engines: the solvers a scene can run (`[[engine]] name = ...`). Each engine kind lives in its own file
// (engine_cvode.cpp, engine_exact.cpp, ...) and is listed once in engine_registry.cpp; the scene parser
// knows engines only through this interface, so a new kind (dsmc, ed, ts, dem, snes) needs no change to it.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "validation/observables/system_state.hpp"

namespace aggkit {

struct Scene;
class SceneTable;

// One number or word an engine reports about its run (step counts, kernel rank, ...), for summary.json.
struct EngineStatistic {
  std::string name;
  std::variant<std::int64_t, double, std::string> value;
};
using EngineStatistics = std::vector<EngineStatistic>;

// What an engine reports while it runs.
struct EngineObserver {
  std::function<void(double t, const SystemState& state)> output;  // at each output time, in order
  std::function<void(double t)> progress;                           // the time reached, as often as it likes
  std::function<void(const std::string& what)> status;              // a stage or count in words, as often as it likes
  std::filesystem::path folder;  // the engine's output folder (exists), for files beyond the series (final.json)
};

class Engine {
 public:
  Engine(std::string name, std::string label) : name_(std::move(name)), label_(std::move(label)) {}
  virtual ~Engine() = default;
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  const std::string& name() const { return name_; }    // the kind: "cvode", "exact", ...
  const std::string& label() const { return label_; }  // unique in a scene: output folder, comparison key
  virtual std::string describe() const = 0;           // the options in one line

  // Runs `scene`, reporting the state at every time of scene.time.outputs in order. Throws InputError
  // for input found bad only now, any other exception if the run fails.
  virtual EngineStatistics run(const Scene& scene, const EngineObserver& observer) const = 0;

 private:
  std::string name_;
  std::string label_;
};

// How an engine kind is read from its `[[engine]]` table.
struct EngineType {
  std::string name;                // the value of `name`
  std::string description;         // one line, for `aggkit` help and messages
  std::vector<std::string> keys;   // its option keys (besides `name` and `label`)
  // Reads the options (unknown keys are already rejected) and checks them against the scene's model and
  // time grid, which are parsed before the engines; throws InputError naming the key.
  std::function<std::unique_ptr<Engine>(const SceneTable& options, std::string label, const Scene& scene)> parse;
  bool needs_model = true;         // kinetic engines need [model]; particle engines need [particles] instead
};

const std::vector<EngineType>& engine_types();
const EngineType* find_engine_type(std::string_view name);  // nullptr if unknown
std::vector<std::string> engine_names();

}  // namespace aggkit

#pragma once
// Engines: the solvers a scene can run (`[[engine]] name = ...`). Each kind is one file engine_<name>.cpp
// defining <name>_engine_type() — its option table (the rows of the settings it configures, declared with
// its physics), what its states give the observables, the files it writes and how it is built — and one
// line in engine_registry.cpp. Particle engines are built on the
// particle runner (particle_runner.hpp), which gives them realizations, threads, final-state observables,
// profiles, conservation checks, timing and snapshots.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "validation/engines/option_table.hpp"
#include "validation/observables/observable.hpp"
#include "validation/scene/scene.hpp"

namespace aggkit {

class RankGroup;  // rank_share.hpp

// One number or word an engine reports about its run (step counts, kernel rank, ...), for summary.json.
struct EngineStatistic {
  std::string name;
  std::variant<std::int64_t, double, std::string> value;
};
using EngineStatistics = std::vector<EngineStatistic>;

// The scene's series observables evaluated on one state (one realization at one output time).
struct Measurement {
  std::vector<double> values;      // observe.series, in order
  double leaked_mass = 0;
  std::vector<double> distribution;  // n_1..n_N at a distribution time (observe.distributions), else empty
  std::vector<double> sizes;         // the sizes of its entries on a graded grid (empty: 1..N)
};

// One value of a final state over an ensemble (final.json: <name> and <name>_stderr).
struct FinalStatistic {
  std::string name;
  double mean = 0;
  double standard_error = 0;  // of the mean; 0 for a single realization
};

// Checkpoints (`aggkit run --checkpoint-every`, `--resume`): what the harness offers an engine that can hand
// it its complete state at an output time. An engine that does not use it runs from its start on a resume.
class EngineCheckpoint {
 public:
  virtual ~EngineCheckpoint() = default;
  // Seconds of wall time between checkpoints; 0: checkpoints are off (save() is then never due).
  virtual double interval() const = 0;
  // The state this engine saved last in the run being resumed; empty when it starts from its beginning.
  virtual const std::string& resumed() const = 0;
  // Whether the engine should hand its state now: the interval has passed since the last checkpoint, or a
  // stop signal (SIGTERM, SIGINT) arrived.
  virtual bool due() const = 0;
  // Writes the run's checkpoint with `state` as this engine's (with what the harness has recorded so far);
  // then, if a stop signal arrived, throws RunInterrupted. Safe to call from several threads.
  virtual void save(std::string state) = 0;
};

// Thrown once the last checkpoint is written after SIGTERM or SIGINT; not a std::exception, so that it passes
// the handlers that record an engine's failure.
struct RunInterrupted {
  int signal = 0;
};

// What an engine reports while it runs.
struct EngineObserver {
  // Evaluates the scene's observables on `state` at output time t; safe to call from several threads.
  std::function<Measurement(double t, const ObservedState& state)> measure;
  // The measurements of every realization at the next output time t, in order of t; with more than one
  // the harness records their mean and standard error.
  std::function<void(double t, std::vector<Measurement> realizations)> record;
  // A particle engine's final-state values (observe.final and its own), once at the end; may be unset.
  std::function<void(std::vector<FinalStatistic> values)> final_state;
  // A particle engine's final configuration of its first realization, once; may be unset.
  std::function<void(const ParticleView& configuration)> final_configuration;
  std::function<void(double t)> progress;                // the time reached, as often as it likes
  std::function<void(const std::string& what)> status;   // a stage or count in words, as often as it likes
  // Something the user should know about a completed run (e.g. densities negative beyond the tolerance):
  // printed as a warning and kept in summary.json; may be unset.
  std::function<void(const std::string& what)> warning;
  std::filesystem::path folder;  // the engine's output folder (exists), for the files it declares
  EngineCheckpoint* checkpoint = nullptr;  // may be unset: no checkpoints
  // The ranks of the job that share the engine's realizations (`mpirun -np K aggkit run`, rank_share.hpp),
  // for an engine that spreads_over_ranks(); unset: this process runs them all. On the ranks other than 0
  // the observer has only `measure` and `ranks`: those ranks record, print and write nothing.
  const RankGroup* ranks = nullptr;

  void output(double t, const ObservedState& state) const { record(t, {measure(t, state)}); }
};

class Engine {
 public:
  // `settings`: the values of its options a run uses (option key -> value, from the rows' fields).
  Engine(std::string name, std::string label, nlohmann::json settings)
      : name_(std::move(name)), label_(std::move(label)), settings_(std::move(settings)) {}
  // An engine without options (or one that does not report them).
  Engine(std::string name, std::string label) : Engine(std::move(name), std::move(label), nlohmann::json::object()) {}
  virtual ~Engine() = default;
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  const std::string& name() const { return name_; }    // the kind: "cvode", "exact", ...
  const std::string& label() const { return label_; }  // unique in a scene: output folder, comparison key
  virtual std::string describe() const = 0;           // the options in one line
  const nlohmann::json& settings() const { return settings_; }  // option key -> the value this engine runs with

  // Runs `scene`, reporting the state at every time of scene.time.outputs in order. Throws InputError
  // for input found bad only now, any other exception if the run fails.
  virtual EngineStatistics run(const Scene& scene, const EngineObserver& observer) const = 0;
  // Whether run() spreads its realizations over observer.ranks (rank_share.hpp); the harness then runs it on
  // every rank (on the ranks other than 0 its statistics are ignored).
  virtual bool spreads_over_ranks() const { return false; }

 private:
  std::string name_;
  std::string label_;
  nlohmann::json settings_;
};

// An engine kind.
struct EngineType {
  std::string name;          // the value of `name`
  std::string description;   // one line, for --help and messages
  OptionTable options;       // its keys besides `name` and `label`
  unsigned provides = need::kinetic;  // what its states give the observables (observable.hpp's need bits)
  bool needs_model = true;            // kinetic engines need [model]; particle engines need [particles]
  std::vector<std::string> files;     // files it writes in its folder besides series.csv and distribution.csv
  // Builds the engine from its checked options; checks them against the scene (InputError naming the key).
  std::function<std::unique_ptr<Engine>(const EngineOptions& options, const EngineSpec& spec, const Scene& scene)> build;
};

const std::vector<EngineType>& engine_types();
const EngineType* find_engine_type(std::string_view name);  // nullptr if unknown
std::vector<std::string> engine_names();

// Builds engine `index` of the scene. InputError, naming the key, for an unknown kind, a bad option, a
// scene without the section it needs, or an observable it cannot give.
std::unique_ptr<Engine> build_engine(const Scene& scene, std::size_t index);
std::vector<std::unique_ptr<Engine>> build_engines(const Scene& scene);  // all, in order; before anything runs

// The scene key of a parameter a solver names in its own terms while an engine runs (solvers/ and particle/
// know no scene keys): an option of the engine's table -> "engine[i].<option>", output_times[k] ->
// "time.outputs[k]", anything else a [model] key ("lambda" -> "model.lambda"). For under_key().
std::function<std::string(const std::string&)> solver_keys(const EngineSpec& spec, const OptionTable& options);

// The engines and observables sections of `aggkit run --help`, from the registries.
std::string engines_help();
std::string observables_help();

}  // namespace aggkit

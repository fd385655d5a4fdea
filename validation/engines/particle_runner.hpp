#pragma once
// The particle runner: what every particle engine (ED, TS, DEM) shares in the harness. An engine supplies
// one realization of its dynamics (ParticleSimulation: a ParticleSource that can advance in time) and its
// option table; the runner gives it
//   * `[particles] realizations` independent runs, each from the scene's start for that realization
//     (particle/common/particle_system.hpp, seeds from particle/common/seeds.hpp), optionally on threads
//     (option `threads`), bit-identical whatever the thread count;
//   * the series: the scene's observables measured on each realization at each output time, recorded by
//     the harness as means with <name>_stderr columns when there are several realizations (a realization
//     that has stopped holds its final state for the later output times);
//   * <label>/final.json: the observe.final values of the final configuration, the engine's own values,
//     wall_seconds, momentum_drift = |P(end) + J_walls − P(0)| / Σ m |v(0)| (absolute when everything
//     starts at rest; P(0) after prepare()), stop_time, each as a mean with <key>_stderr;
//     <label>/<profile>.csv for profiles (particle_outputs.hpp);
//   * with observe.snapshots, the first realization's final configuration as final.vtu (cluster, radius,
//     velocity, and angular_velocity where the engine integrates rotation) and final.png;
//   * with observe.times_ff = [k, ...], the observe.final values and the engine's state_values() at
//     t = k t_ff of each realization (t_ff from the engine: dem with gravity) as <name>_at_<k>tff, with
//     time_ff_at_<k>tff the time reached over t_ff (within half a step of k); NaN for a time the run does not
//     reach (beyond time.end, or after the engine's stop rule ended it);
//   * progress in words, summary statistics (the engine's counters summed over realizations);
//   * checkpoints (EngineCheckpoint, option checkpoint_every): at every output time each realization keeps
//     its state — its series so far and, for an engine that saves its state, the simulation's — and a
//     finished one its result; a checkpoint writes them all. On a resume finished realizations are not run
//     again, the others continue from their state (or, for an engine that cannot save one, from their start),
//     so the outputs are those of an uninterrupted run, bit for bit (wall_seconds aside).
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "particle/common/checkpoint.hpp"
#include "particle/common/vector3.hpp"
#include "validation/engines/engine.hpp"
#include "validation/observables/particle_view.hpp"

namespace aggkit {

using StatusSink = std::function<void(const std::string& what)>;

// One realization of a particle engine.
class ParticleSimulation : public ParticleSource {
 public:
  // Before the clock starts (ED: the elastic thermalisation); may report its stage through `status`.
  virtual void prepare(const StatusSink& status) { (void)status; }
  // Advances to time t, or until the engine's stop rule holds; true once it holds (nothing more to do).
  virtual bool advance(double t, const StatusSink& status) = 0;
  // After the last output time: runs on if the stop rule asks for it (ED: a cluster count not yet reached).
  virtual void finish(double end, const StatusSink& status) { (void)end, (void)status; }
  virtual double time() const = 0;
  virtual Vector3 momentum() const;                       // Σ m v; by default over the particles
  virtual Vector3 wall_impulse() const { return {0, 0, 0}; }  // momentum given to the walls so far
  // For the .vtu snapshot: per-particle radii (empty: the configuration's one radius) and angular velocities
  // (empty: rotation is not integrated, and the snapshot has no angular_velocity array).
  virtual std::vector<double> radii() const { return {}; }
  virtual std::vector<Vector3> angular_velocities() const { return {}; }
  // The engine's own entries of final.json (after the observables) and counters for summary.json (summed).
  virtual std::vector<std::pair<std::string, double>> final_values() const { return {}; }
  virtual std::vector<std::pair<std::string, std::int64_t>> counters() const { return {}; }
  // The free-fall time of the realization's start (observe.times_ff); NaN for an engine without one.
  virtual double free_fall_time() const;
  // Values of the current state the engine computes itself (DEM: K/|P|), recorded with observe.final at
  // observe.times_ff; by default none.
  virtual std::vector<std::pair<std::string, double>> state_values() const { return {}; }
  // Checkpoints: the complete state after advance() returned, such that restore() into a simulation just
  // started for the same realization (without prepare()) continues to the same bits. An engine that does not
  // save its state restarts the realization from its start on a resume.
  virtual bool saves_state() const { return false; }
  virtual void save(StateWriter& out) const { (void)out; }
  virtual void restore(StateReader& in) { (void)in; }
};

// The values of the final-configuration observables among `names` (observe.final less the series measures
// and profiles) on `state`, each name followed by `suffix`: what final.json holds for them at the end, and
// at observe.times_ff ("_at_2tff") or at T_agg ("_at_agg") for the engines that record those.
std::vector<std::pair<std::string, double>> configuration_values(const std::vector<std::string>& names, const ParticleView& state,
                                                                 const std::string& suffix);

// The suffix of the values recorded at t = k t_ff (observe.times_ff): "_at_<k>tff", k written shortest.
std::string free_fall_suffix(double k);

// A particle engine as its file declares it.
struct ParticleEngineKind {
  std::string name;
  std::string description;
  OptionTable options;  // its own keys; the runner adds `threads`
  // What the engine runs: checks its options and the scene's [particles] (InputError naming the key for a
  // form it cannot use), then returns how to start realization r and a one-line description.
  struct Setup {
    std::function<std::unique_ptr<ParticleSimulation>(std::size_t realization)> start;
    std::string description;
    nlohmann::json settings;  // option key -> the value the run uses (the rows' values of its settings)
    std::vector<std::string> warnings;  // what the user should know about the run (EngineObserver::warning)
  };
  std::function<Setup(const EngineOptions& options, const Scene& scene)> setup;
  // What its states give the observables: the configuration, and for engines of colliding particles
  // need::collisions and need::virial (ParticleSource::collision_statistics). An observable needing the
  // virial is refused unless the box is periodic.
  unsigned provides = need::particles;
};

// The key and name of the first observable of the scene (series, then final) that needs any of `needs`
// bits; std::nullopt if none does. For engines whose options decide what they can give.
std::optional<std::pair<std::string, std::string>> observable_needing(const Scene& scene, unsigned needs);

// The engine type of a particle engine: the runner's options and files added to the kind's.
EngineType particle_engine_type(ParticleEngineKind kind);

}  // namespace aggkit

#include "validation/engines/particle_runner.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "analysis/input_error.hpp"
#include "validation/engines/particle_outputs.hpp"
#include "validation/engines/rank_share.hpp"
#include "validation/io/atomic_file.hpp"
#include "validation/io/particle_snapshot.hpp"
#include "validation/io/trajectory.hpp"
#include "validation/io/text.hpp"

namespace aggkit {

double ParticleSimulation::free_fall_time() const { return std::numeric_limits<double>::quiet_NaN(); }

std::vector<std::pair<std::string, double>> configuration_values(const std::vector<std::string>& names, const ParticleView& state,
                                                                 const std::string& suffix) {
  std::vector<std::pair<std::string, double>> values;
  for (const std::string& name : names) {
    const Observable observable = *Observable::from_name(name);
    if (observable.is_series_measure() || observable.is_profile()) continue;
    for (auto& [key, value] : observable.final_values(state)) values.emplace_back(key + suffix, value);
  }
  return values;
}

std::string free_fall_suffix(double k) { return "_at_" + shortest_text(k) + "tff"; }

Vector3 ParticleSimulation::momentum() const {
  const std::vector<Vector3> v = velocities();
  const std::vector<double> m = masses();
  Vector3 p{0, 0, 0};
  for (std::size_t i = 0; i < v.size(); ++i) p = p + m[i] * v[i];
  return p;
}

namespace {

// What one realization leaves for the ensemble.
struct RealizationResult {
  std::vector<Measurement> series;                    // per output time
  std::vector<std::pair<std::string, double>> finals; // final.json entries, in order
  NamedProfiles profiles;
  std::vector<std::pair<std::string, std::int64_t>> counters;
  std::string picture = "not requested";
  bool resumed = false;  // continued from a checkpoint (its state, or its result), not from its start
};

template <class T>
void put_pairs(StateWriter& out, const std::vector<std::pair<std::string, T>>& pairs) {
  out.put(std::uint64_t(pairs.size()));
  for (const auto& [key, value] : pairs) {
    out.put(key);
    out.put(value);
  }
}

template <class T>
void get_pairs(StateReader& in, std::vector<std::pair<std::string, T>>& pairs) {
  pairs.resize(in.length(sizeof(std::uint64_t) + sizeof(T)));  // key length, value
  for (auto& [key, value] : pairs) {
    in.get(key);
    in.get(value);
  }
}

// The part of a realization's result every state holds: its series and values so far.
void put_partial(StateWriter& out, const RealizationResult& result) {
  out.put(std::uint64_t(result.series.size()));
  for (const auto& m : result.series) put_measurement(out, m);
  put_pairs(out, result.finals);
}

void get_partial(StateReader& in, RealizationResult& result) {
  result.series.resize(in.length(4 * sizeof(std::uint64_t)));  // a measurement: three lengths and a leak
  for (auto& m : result.series) m = get_measurement(in);
  get_pairs(in, result.finals);
}

void put_result(StateWriter& out, const RealizationResult& result) {
  put_partial(out, result);
  out.put(std::uint64_t(result.profiles.size()));
  for (const auto& [name, profile] : result.profiles) {
    out.put(name);
    out.put(profile.x_name);
    out.put(profile.y_name);
    out.put(profile.x);
    out.put(profile.y);
  }
  put_pairs(out, result.counters);
  out.put(result.picture);
}

RealizationResult get_result(StateReader& in) {
  RealizationResult result;
  get_partial(in, result);
  result.profiles.resize(in.length(5 * sizeof(std::uint64_t)));  // five lengths
  for (auto& [name, profile] : result.profiles) {
    in.get(name);
    in.get(profile.x_name);
    in.get(profile.y_name);
    in.get(profile.x);
    in.get(profile.y);
  }
  get_pairs(in, result.counters);
  in.get(result.picture);
  return result;
}

// A snapshot of the simulation's state: the final one, or a frame of the trajectory.
void write_snapshot(const std::filesystem::path& path, const ParticleSimulation& simulation) {
  const ParticleView state(simulation);
  write_vtu_snapshot(path, state.configuration(), state.cluster_labels(), state.velocities(), simulation.radii(),
                     simulation.angular_velocities());
}

// What a checkpoint holds of each realization: nothing yet (it starts from its start), its state at an
// output time, or its result.
enum class RealizationStage : std::uint8_t { start = 0, running = 1, finished = 2 };

class RealizationStates {
 public:
  explicit RealizationStates(std::size_t realizations) : states_(realizations) {}
  void set(std::size_t r, std::string state) {
    std::lock_guard lock(lock_);
    states_[r] = std::move(state);
  }
  std::string payload() const {
    std::lock_guard lock(lock_);
    StateWriter out;
    out.put(std::uint64_t(states_.size()));
    for (const auto& state : states_) {
      if (state.empty()) out.put(std::string(1, char(RealizationStage::start)));
      else out.put(state);
    }
    return out.take();
  }
  // The states of a checkpoint's payload, one per realization (CheckpointError unless `realizations` of them).
  static std::vector<std::string> read(const std::string& payload, std::size_t realizations) {
    StateReader in(payload);
    in.expect(std::uint64_t(realizations), "number of realizations");
    std::vector<std::string> states(realizations);
    for (auto& state : states) in.get(state);
    in.expect_end();
    return states;
  }

 private:
  mutable std::mutex lock_;
  std::vector<std::string> states_;
};

// Where a running realization stands: what its checkpoint keeps beside its partial result and the engine's
// state.
struct RealizationProgress {
  std::uint64_t next_output = 0, next_ff = 0;  // the next output time and free-fall time to record
  bool stopped = false;                          // by the engine's stop rule
  Vector3 p0{0, 0, 0};                           // momentum plus wall impulse at the start
  double momentum_scale = 0;                     // Σ m |v| at the start
  double earlier_wall = 0;                       // wall seconds of the runs before a resume
};

// Realization r's start: prepared, its first trajectory frame written (r = 0), its momentum taken.
RealizationProgress start_realization(const Scene& scene, const EngineObserver& observer, std::size_t r,
                                      ParticleSimulation& simulation, const StatusSink& status) {
  RealizationProgress at;
  simulation.prepare(status);
  if (r == 0 && scene.observe.frame_every > 0) {  // a fresh trajectory, from t = 0
    std::filesystem::remove_all(observer.folder / "trajectory");
    std::filesystem::create_directories(observer.folder / "trajectory");
    write_snapshot(trajectory_frame(observer.folder, 0), simulation);
  }
  at.p0 = simulation.momentum() + simulation.wall_impulse();
  const std::vector<Vector3> v = simulation.velocities();
  const std::vector<double> m = simulation.masses();
  for (std::size_t i = 0; i < v.size(); ++i) at.momentum_scale += m[i] * norm(v[i]);
  return at;
}

// A running realization's state after output k - 1 (`k` the next output), for a checkpoint.
std::string running_state(const RealizationResult& result, std::uint64_t k, const RealizationProgress& at, double wall,
                          const ParticleSimulation& simulation) {
  StateWriter out;
  out.put(RealizationStage::running);
  put_partial(out, result);
  out.put(k);
  out.put(at.next_ff);
  out.put(std::uint8_t(at.stopped));
  out.put(at.p0);
  out.put(at.momentum_scale);
  out.put(wall);
  simulation.save(out);
  return out.take();
}

// ... read back (after its stage), the engine's state restored.
RealizationProgress read_running_state(StateReader& saved, RealizationResult& result, ParticleSimulation& simulation,
                                       std::size_t outputs) {
  RealizationProgress at;
  get_partial(saved, result);
  saved.get(at.next_output);
  saved.get(at.next_ff);
  at.stopped = saved.read<std::uint8_t>() != 0;
  saved.get(at.p0);
  saved.get(at.momentum_scale);
  saved.get(at.earlier_wall);
  simulation.restore(saved);
  saved.expect_end();
  if (at.next_output > outputs || result.series.size() != at.next_output)
    throw CheckpointError("the checkpoint's output count does not fit this scene's output times");
  result.resumed = true;
  return at;
}

// The final.json entries of observe.times_ff k (the configuration's values, the engine's, the time in
// t_ff), NaN where not `reached`.
void add_free_fall_values(const Scene& scene, const ParticleSimulation& simulation, double k, double free_fall, bool reached,
                          RealizationResult& result) {
  const ParticleView state(simulation);
  auto values = configuration_values(scene.observe.final_state, state, free_fall_suffix(k));
  for (auto& entry : simulation.state_values()) values.emplace_back(entry.first + free_fall_suffix(k), entry.second);
  values.emplace_back("time_ff" + free_fall_suffix(k), simulation.time() / free_fall);
  for (auto& [key, value] : values) result.finals.emplace_back(key, reached ? value : std::numeric_limits<double>::quiet_NaN());
}

// The final.json entries and profiles of a finished realization.
void add_final_values(const Scene& scene, ParticleSimulation& simulation, const RealizationProgress& at, double wall,
                      RealizationResult& result) {
  const ParticleView final(simulation);
  std::vector<std::pair<std::string, double>> at_end = configuration_values(scene.observe.final_state, final, "");
  result.finals.insert(result.finals.begin(), at_end.begin(), at_end.end());  // first in final.json, as before
  for (const std::string& name : scene.observe.final_state) {
    const Observable observable = *Observable::from_name(name);
    if (observable.is_profile()) result.profiles.emplace_back(name, observable.profile(final));
  }
  for (auto& entry : simulation.final_values()) result.finals.push_back(std::move(entry));
  const double drift = norm(simulation.momentum() + simulation.wall_impulse() - at.p0);
  result.finals.emplace_back("wall_seconds", wall);
  result.finals.emplace_back("momentum_drift", at.momentum_scale > 0 ? drift / at.momentum_scale : drift);
  result.finals.emplace_back("stop_time", simulation.time());
  result.counters = simulation.counters();
}

// What realization 0 alone writes at its end: the final configuration to the observer, the trajectory's
// collection, the snapshot and picture.
void write_first_realization(const Scene& scene, const EngineObserver& observer, const ParticleSimulation& simulation,
                             RealizationResult& result) {
  const ParticleView final(simulation);
  if (observer.final_configuration) observer.final_configuration(final);
  if (scene.observe.frame_every > 0) {
    std::vector<double> times{0.0};
    for (std::size_t k : scene.observe.frame_outputs) times.push_back(scene.time.outputs[k]);
    write_trajectory_collection(observer.folder, times);
  }
  if (scene.observe.snapshots) {
    write_snapshot(observer.folder / "final.vtu", simulation);
    std::string error;
    result.picture = write_cluster_picture(observer.folder / "final.png", final.configuration(), final.cluster_labels(), &error)
                         ? "final.png"
                         : "failed: " + error;
  }
}

// run(k) for each pending realization on `workers` threads; the first failure is rethrown after every
// thread has stopped (`report` also guards the failure).
void run_on_threads(const std::vector<std::size_t>& pending, std::size_t workers, std::mutex& report,
                    const std::function<void(std::size_t)>& run) {
  if (workers <= 1) {
    for (std::size_t r : pending) run(r);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::vector<std::thread> pool;
  for (std::size_t w = 0; w < workers; ++w)
    pool.emplace_back([&] {
      for (std::size_t k; (k = next++) < pending.size();) {
        try {
          run(pending[k]);
        } catch (...) {
          std::lock_guard lock(report);
          if (!failure) failure = std::current_exception();
          next = pending.size();
        }
      }
    });
  for (auto& thread : pool) thread.join();
  if (failure) std::rethrow_exception(failure);
}

// The ensemble's series, final.json and profiles (rank 0).
void record_ensemble(const Scene& scene, const EngineObserver& observer, std::vector<RealizationResult>& results) {
  const std::vector<double>& outputs = scene.time.outputs;
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    std::vector<Measurement> at_k;
    for (auto& result : results) at_k.push_back(std::move(result.series[k]));
    observer.record(outputs[k], std::move(at_k));
  }
  FinalAverages finals;
  std::vector<NamedProfiles> profiles;
  for (const auto& result : results) {
    for (const auto& [key, value] : result.finals) finals.add(key, value);
    profiles.push_back(result.profiles);
  }
  write_file_atomically(observer.folder / "final.json", finals.json(results.size()));
  if (observer.final_state) observer.final_state(finals.statistics());
  write_final_profiles(observer.folder, profiles);
}

class ParticleEngine final : public Engine {
 public:
  ParticleEngine(std::string name, std::string label, ParticleEngineKind::Setup setup, std::size_t threads,
                 double max_wall_seconds)
      : Engine(std::move(name), std::move(label), setup.settings), setup_(std::move(setup)), threads_(threads),
        max_wall_seconds_(max_wall_seconds) {}

  std::string describe() const override {
    return setup_.description + (threads_ != 1 ? ", " + (threads_ == 0 ? std::string("all cores") : std::to_string(threads_) + " threads") : "");
  }

  bool spreads_over_ranks() const override { return true; }

  EngineStatistics run(const Scene& scene, const EngineObserver& observer) const override {
    if (observer.warning)
      for (const std::string& warning : setup_.warnings) observer.warning(warning);
    const std::size_t realizations = scene.particles->realizations;
    std::vector<RealizationResult> results(realizations);
    std::mutex report;  // progress and status lines come from every thread

    // Checkpoints: the states of a resumed run; finished realizations are taken as they are.
    EngineCheckpoint* checkpoint = observer.checkpoint && observer.checkpoint->interval() > 0 ? observer.checkpoint : nullptr;
    RealizationStates states(realizations);
    std::vector<std::string> resumed(realizations);
    std::vector<bool> finished(realizations, false);
    if (observer.checkpoint && !observer.checkpoint->resumed().empty())
      take_finished(observer.checkpoint->resumed(), results, states, resumed, finished);
    // With several ranks (rank_share.hpp) each runs its share of the realizations, and rank 0 takes every
    // result in realization order; checkpoints are then off (the harness refuses them).
    const RankGroup* ranks = shared_ranks(observer.ranks);
    const std::vector<std::size_t> mine = realizations_of_rank(realizations, ranks);
    std::vector<std::size_t> pending;
    for (std::size_t r : mine)
      if (!finished[r]) pending.push_back(r);
    std::size_t workers = threads_ == 0 ? std::max(1u, std::thread::hardware_concurrency()) : threads_;
    workers = std::min(workers, mine.size());
    results = gather_realization_values<RealizationResult>(
        ranks, realizations,
        [&](const std::vector<std::size_t>& own) {
          run_on_threads(pending, workers, report, [&](std::size_t r) {
            results[r] = run_one(scene, observer, r, report, resumed[r], checkpoint ? &states : nullptr, checkpoint);
          });
          std::vector<RealizationResult> mine;
          for (std::size_t r : own) mine.push_back(std::move(results[r]));
          return mine;
        },
        put_result, get_result);
    if (ranks && ranks->rank() != 0) return {};  // rank 0 records and writes
    record_ensemble(scene, observer, results);
    return statistics(scene, observer, results, workers, ranks);
  }

 private:
  // The realizations a checkpoint holds finished, taken as they are; the states of the others kept in
  // `resumed`.
  void take_finished(const std::string& checkpoint, std::vector<RealizationResult>& results, RealizationStates& states,
                     std::vector<std::string>& resumed, std::vector<bool>& finished) const {
    try {
      resumed = RealizationStates::read(checkpoint, results.size());
      for (std::size_t r = 0; r < results.size(); ++r) {
        StateReader in(resumed[r]);
        if (in.read<RealizationStage>() != RealizationStage::finished) continue;
        results[r] = get_result(in);
        in.expect_end();
        results[r].resumed = true;
        finished[r] = true;
        states.set(r, std::move(resumed[r]));
      }
    } catch (const CheckpointError& e) {
      throw InputError("--resume", label(), std::string("a checkpoint this engine can continue from; ") + e.what());
    }
  }

  EngineStatistics statistics(const Scene& scene, const EngineObserver& observer, const std::vector<RealizationResult>& results,
                              std::size_t workers, const RankGroup* ranks) const {
    EngineStatistics statistics{{"particles", scene.particles->describe()},
                                {"realizations", std::int64_t(results.size())},
                                {"threads", std::int64_t(workers)}};
    if (ranks) statistics.push_back({"ranks", std::int64_t(ranks->size())});  // threads: those of rank 0
    for (std::size_t c = 0; c < results.front().counters.size(); ++c) {
      std::int64_t total = 0;
      for (const auto& result : results) total += result.counters[c].second;
      statistics.push_back({results.front().counters[c].first, total});
    }
    statistics.push_back({"picture", results.front().picture});
    // A resume: how many realizations continued from the checkpoint (the others started again).
    if (observer.checkpoint && !observer.checkpoint->resumed().empty()) {
      std::int64_t resumed = 0;
      for (const auto& result : results) resumed += result.resumed;
      statistics.push_back({"resumed_realizations", resumed});
    }
    return statistics;
  }

  // Realization r from its start, or from `resumed` (its state in a checkpoint: a stage, then what it holds).
  // With `states`, its state is kept at every output time and the checkpoint written when due.
  RealizationResult run_one(const Scene& scene, const EngineObserver& observer, std::size_t r, std::mutex& report,
                            const std::string& resumed, RealizationStates* states, EngineCheckpoint* checkpoint) const {
    const std::size_t realizations = scene.particles->realizations;
    const std::string prefix =
        realizations > 1 ? "realization " + std::to_string(r + 1) + "/" + std::to_string(realizations) + ", " : "";
    const auto started = std::chrono::steady_clock::now();
    const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(); };
    // The wall-time budget is checked whenever the engine reports (ED: every 2^16 events and every chunk).
    const StatusSink status = [&](const std::string& what) {
      if (max_wall_seconds_ > 0 && seconds() > max_wall_seconds_)
        throw std::runtime_error("stopped: the wall-time budget of " + std::to_string(max_wall_seconds_) +
                                 " s (engine option max_wall_seconds) ran out at " + what);
      if (!observer.status) return;
      std::lock_guard lock(report);
      observer.status(prefix + what);
    };
    RealizationResult result;
    const std::unique_ptr<ParticleSimulation> simulation = setup_.start(r);
    const std::vector<double>& outputs = scene.time.outputs;
    RealizationProgress at;
    StateReader saved(resumed);
    if (!resumed.empty() && saved.read<RealizationStage>() == RealizationStage::running) {
      try {
        at = read_running_state(saved, result, *simulation, outputs.size());
      } catch (const CheckpointError& e) {
        throw InputError("--resume", label(), "a checkpoint this engine can continue from; realization " + std::to_string(r + 1) +
                                                  ": " + e.what());
      }
    } else {
      at = start_realization(scene, observer, r, *simulation, status);
    }
    // observe.times_ff: the state at t = k t_ff, between the output times.
    const std::vector<double>& times_ff = scene.observe.times_ff;
    const double free_fall = times_ff.empty() ? 0.0 : simulation->free_fall_time();
    if (!times_ff.empty() && !(free_fall > 0 && std::isfinite(free_fall)))
      throw InputError("observe.times_ff", "[" + shortest_text(times_ff.front()) + ", ...]",
                       "free-fall times only with an engine that has one (dem with gravity)");
    const auto record_ff = [&](double until) {
      for (; at.next_ff < times_ff.size() && (times_ff[at.next_ff] * free_fall <= until || until < 0); ++at.next_ff) {
        const double k = times_ff[at.next_ff];
        // Reached unless the run has stopped (its stop rule, or time.end: until < 0) before k t_ff.
        const bool reached = until >= 0 && !at.stopped && !(at.stopped = simulation->advance(k * free_fall, status));
        add_free_fall_values(scene, *simulation, k, free_fall, reached, result);
      }
    };
    for (std::uint64_t k = at.next_output; k < outputs.size(); ++k) {
      const double t = outputs[k];
      record_ff(t);
      if (!at.stopped) at.stopped = simulation->advance(t, status);
      result.series.push_back(observer.measure(t, ParticleView(*simulation)));
      if (r == 0) {  // the trajectory's frame of this output, if it has one
        const auto& frames = scene.observe.frame_outputs;
        if (const auto frame = std::find(frames.begin(), frames.end(), k); frame != frames.end())
          write_snapshot(trajectory_frame(observer.folder, std::size_t(frame - frames.begin()) + 1), *simulation);
      }
      if (r == 0 && observer.progress) {
        std::lock_guard lock(report);
        observer.progress(t);
      }
      if (!states) continue;
      // This realization's state after output k (when the engine can save it); the checkpoint when due.
      if (simulation->saves_state()) states->set(r, running_state(result, k + 1, at, at.earlier_wall + seconds(), *simulation));
      if (checkpoint->due()) checkpoint->save(states->payload());
    }
    record_ff(-1);  // beyond time.end: not reached
    if (!at.stopped) simulation->finish(scene.time.end, status);
    add_final_values(scene, *simulation, at, at.earlier_wall + seconds(), result);
    if (r == 0) write_first_realization(scene, observer, *simulation, result);
    if (states) {
      StateWriter out;
      out.put(RealizationStage::finished);
      put_result(out, result);
      states->set(r, out.take());
      if (checkpoint->due()) checkpoint->save(states->payload());
    }
    return result;
  }

  ParticleEngineKind::Setup setup_;
  std::size_t threads_;
  double max_wall_seconds_;
};

}  // namespace

std::optional<std::pair<std::string, std::string>> observable_needing(const Scene& scene, unsigned needs) {
  for (std::size_t i = 0; i < scene.observe.series.size(); ++i)
    if (scene.observe.series[i].needs() & needs) return std::pair{"observe.series[" + std::to_string(i) + "]", scene.observe.series[i].name()};
  for (std::size_t i = 0; i < scene.observe.final_state.size(); ++i)
    if (Observable::from_name(scene.observe.final_state[i])->needs() & needs)
      return std::pair{"observe.final[" + std::to_string(i) + "]", scene.observe.final_state[i]};
  return std::nullopt;
}

namespace {

// What the runner adds to every particle engine.
struct RunnerSettings {
  std::size_t threads = 1;
  double max_wall_seconds = 0;  // 0: none
  double checkpoint_every = 0;  // 0: none
};

const OptionRows<RunnerSettings>& runner_rows() {
  using B = Bind<RunnerSettings>;
  static const OptionRows<RunnerSettings> rows{{
      B::integer("threads", &RunnerSettings::threads, closed(0, 4096),
                 "realizations run at once (0: one per core); results do not depend on it"),
      B::number("max_wall_seconds", &RunnerSettings::max_wall_seconds, closed(0.0, 1e9),
                "wall-time budget of each realization; the run fails when it is spent (0: none)"),
      B::number("checkpoint_every", &RunnerSettings::checkpoint_every, closed(0.0, 1e9),
                "wall seconds between checkpoints, taken at output times (0: none; aggkit run --checkpoint-every "
                "overrides it)"),
  }};
  return rows;
}

}  // namespace

EngineType particle_engine_type(ParticleEngineKind kind) {
  OptionTable options = kind.options;
  const OptionTable runner = runner_rows().table();
  options.insert(options.end(), runner.begin(), runner.end());
  std::vector<std::string> files{"final.json", "final.vtu", "final.png", "trajectory.pvd"};
  for (auto& f : profile_files()) files.push_back(f);
  auto setup = kind.setup;
  const std::string name = kind.name;
  return {kind.name, kind.description, options, kind.provides, /*needs_model=*/false, files,
          [setup, name](const EngineOptions& given, const EngineSpec& spec, const Scene& scene) -> std::unique_ptr<Engine> {
            // The virial theorem's pressure holds for pair forces in a periodic box; walls would add their own
            // virial (and an excluded layer of one radius), open space has no volume.
            if (const auto asked = observable_needing(scene, need::virial); asked && scene.particles->box.boundary != Boundary::periodic)
              throw InputError(asked->first, "\"" + asked->second + "\"",
                               "an observable of a periodic box (particles.boundary = \"periodic\"): the pressure from the "
                               "virial theorem needs one");
            RunnerSettings runner;
            given.read(runner_rows(), runner);
            ParticleEngineKind::Setup run = setup(given, scene);
            run.settings.update(runner_rows().values(runner));
            return std::make_unique<ParticleEngine>(name, spec.label, std::move(run), runner.threads, runner.max_wall_seconds);
          }};
}

}  // namespace aggkit

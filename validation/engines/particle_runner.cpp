#include "validation/engines/particle_runner.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
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
    const ParticleSystem& system = *scene.particles;
    const std::size_t realizations = system.realizations;
    std::vector<RealizationResult> results(realizations);
    std::mutex report;  // progress and status lines come from every thread

    // Checkpoints: the states of a resumed run; finished realizations are taken as they are.
    EngineCheckpoint* checkpoint = observer.checkpoint && observer.checkpoint->interval() > 0 ? observer.checkpoint : nullptr;
    RealizationStates states(realizations);
    std::vector<std::string> resumed(realizations);
    std::vector<bool> finished(realizations, false);
    if (observer.checkpoint && !observer.checkpoint->resumed().empty()) {
      try {
        resumed = RealizationStates::read(observer.checkpoint->resumed(), realizations);
        for (std::size_t r = 0; r < realizations; ++r) {
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
    // With several ranks (rank_share.hpp) each runs its share of the realizations, and rank 0 takes every
    // result in realization order; checkpoints are then off (the harness refuses them).
    const RankGroup* ranks = shared_ranks(observer.ranks);
    const std::vector<std::size_t> mine = realizations_of_rank(realizations, ranks);
    std::vector<std::size_t> pending;
    for (std::size_t r : mine)
      if (!finished[r]) pending.push_back(r);
    const auto run_realization = [&](std::size_t r) {
      results[r] = run_one(scene, observer, r, report, resumed[r], checkpoint ? &states : nullptr, checkpoint);
    };

    std::size_t workers = threads_ == 0 ? std::max(1u, std::thread::hardware_concurrency()) : threads_;
    workers = std::min(workers, mine.size());
    const auto run_pending = [&] {
      if (workers <= 1) {
        for (std::size_t r : pending) run_realization(r);
        return;
      }
      std::atomic<std::size_t> next{0};
      std::exception_ptr failure;
      std::vector<std::thread> pool;
      for (std::size_t w = 0; w < workers; ++w)
        pool.emplace_back([&] {
          for (std::size_t k; (k = next++) < pending.size();) {
            try {
              run_realization(pending[k]);
            } catch (...) {
              std::lock_guard lock(report);
              if (!failure) failure = std::current_exception();
              next = pending.size();
            }
          }
        });
      for (auto& thread : pool) thread.join();
      if (failure) std::rethrow_exception(failure);
    };
    results = gather_realization_values<RealizationResult>(
        ranks, realizations,
        [&](const std::vector<std::size_t>& own) {
          run_pending();
          std::vector<RealizationResult> mine;
          for (std::size_t r : own) mine.push_back(std::move(results[r]));
          return mine;
        },
        put_result, get_result);
    if (ranks && ranks->rank() != 0) return {};  // rank 0 records and writes

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
    write_file_atomically(observer.folder / "final.json", finals.json(realizations));
    if (observer.final_state) observer.final_state(finals.statistics());
    write_final_profiles(observer.folder, profiles);

    EngineStatistics statistics{{"particles", system.describe()},
                                {"realizations", std::int64_t(realizations)},
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

 private:
  // Realization r from its start, or from `resumed` (its state in a checkpoint: a stage, then what it holds).
  // With `states`, its state is kept at every output time and the checkpoint written when due.
  RealizationResult run_one(const Scene& scene, const EngineObserver& observer, std::size_t r, std::mutex& report,
                            const std::string& resumed, RealizationStates* states, EngineCheckpoint* checkpoint) const {
    const std::size_t realizations = scene.particles->realizations;
    const std::string prefix =
        realizations > 1 ? "realization " + std::to_string(r + 1) + "/" + std::to_string(realizations) + ", " : "";
    const auto started = std::chrono::steady_clock::now();
    // The wall-time budget is checked whenever the engine reports (ED: every 2^16 events and every chunk).
    const StatusSink status = [&](const std::string& what) {
      if (max_wall_seconds_ > 0 &&
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() > max_wall_seconds_)
        throw std::runtime_error("stopped: the wall-time budget of " + std::to_string(max_wall_seconds_) +
                                 " s (engine option max_wall_seconds) ran out at " + what);
      if (!observer.status) return;
      std::lock_guard lock(report);
      observer.status(prefix + what);
    };
    RealizationResult result;
    const std::unique_ptr<ParticleSimulation> simulation = setup_.start(r);
    Vector3 p0{0, 0, 0};
    double momentum_scale = 0;
    const std::vector<double>& outputs = scene.time.outputs;
    bool stopped = false;
    std::uint64_t next_output = 0, next_ff = 0;
    double earlier_wall = 0;  // of the runs before a resume
    StateReader saved(resumed);
    if (!resumed.empty() && saved.read<RealizationStage>() == RealizationStage::running) {
      try {
        get_partial(saved, result);
        saved.get(next_output);
        saved.get(next_ff);
        stopped = saved.read<std::uint8_t>() != 0;
        saved.get(p0);
        saved.get(momentum_scale);
        saved.get(earlier_wall);
        simulation->restore(saved);
        saved.expect_end();
        if (next_output > outputs.size() || result.series.size() != next_output)
          throw CheckpointError("the checkpoint's output count does not fit this scene's output times");
        result.resumed = true;
      } catch (const CheckpointError& e) {
        throw InputError("--resume", label(), "a checkpoint this engine can continue from; realization " + std::to_string(r + 1) +
                                                  ": " + e.what());
      }
    } else {
      simulation->prepare(status);
      if (r == 0 && scene.observe.frame_every > 0) {  // a fresh trajectory, from t = 0
        std::filesystem::remove_all(observer.folder / "trajectory");
        std::filesystem::create_directories(observer.folder / "trajectory");
        write_snapshot(trajectory_frame(observer.folder, 0), *simulation);
      }
      p0 = simulation->momentum() + simulation->wall_impulse();
      const std::vector<Vector3> v = simulation->velocities();
      const std::vector<double> m = simulation->masses();
      for (std::size_t i = 0; i < v.size(); ++i) momentum_scale += m[i] * norm(v[i]);
    }
    // Keeps this realization's state after output k (when the engine can save it) and writes the checkpoint
    // when it is due.
    const auto keep_state = [&](std::uint64_t k) {
      if (!states) return;
      if (simulation->saves_state()) {
        StateWriter out;
        out.put(RealizationStage::running);
        put_partial(out, result);
        out.put(k);
        out.put(next_ff);
        out.put(std::uint8_t(stopped));
        out.put(p0);
        out.put(momentum_scale);
        out.put(earlier_wall + std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
        simulation->save(out);
        states->set(r, out.take());
      }
      if (checkpoint->due()) checkpoint->save(states->payload());
    };
    // observe.times_ff: the state at t = k t_ff, between the output times.
    const std::vector<double>& times_ff = scene.observe.times_ff;
    const double free_fall = times_ff.empty() ? 0.0 : simulation->free_fall_time();
    if (!times_ff.empty() && !(free_fall > 0 && std::isfinite(free_fall)))
      throw InputError("observe.times_ff", "[" + shortest_text(times_ff.front()) + ", ...]",
                       "free-fall times only with an engine that has one (dem with gravity)");
    const auto record_ff = [&](double until) {
      for (; next_ff < times_ff.size() && (times_ff[next_ff] * free_fall <= until || until < 0); ++next_ff) {
        const double k = times_ff[next_ff];
        // Reached unless the run has stopped (its stop rule, or time.end: until < 0) before k t_ff.
        const bool reached = until >= 0 && !stopped && !(stopped = simulation->advance(k * free_fall, status));
        const ParticleView state(*simulation);
        auto values = configuration_values(scene.observe.final_state, state, free_fall_suffix(k));
        for (auto& entry : simulation->state_values()) values.emplace_back(entry.first + free_fall_suffix(k), entry.second);
        values.emplace_back("time_ff" + free_fall_suffix(k), simulation->time() / free_fall);
        for (auto& [key, value] : values) result.finals.emplace_back(key, reached ? value : std::numeric_limits<double>::quiet_NaN());
      }
    };
    for (std::uint64_t k = next_output; k < outputs.size(); ++k) {
      const double t = outputs[k];
      record_ff(t);
      if (!stopped) stopped = simulation->advance(t, status);
      result.series.push_back(observer.measure(t, ParticleView(*simulation)));
      if (r == 0) {  // the trajectory's frame of this output, if it has one
        const auto& frames = scene.observe.frame_outputs;
        if (const auto at = std::find(frames.begin(), frames.end(), k); at != frames.end())
          write_snapshot(trajectory_frame(observer.folder, std::size_t(at - frames.begin()) + 1), *simulation);
      }
      if (r == 0 && observer.progress) {
        std::lock_guard lock(report);
        observer.progress(t);
      }
      keep_state(k + 1);
    }
    record_ff(-1);  // beyond time.end: not reached
    if (!stopped) simulation->finish(scene.time.end, status);
    const double wall = earlier_wall + std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

    const ParticleView final(*simulation);
    std::vector<std::pair<std::string, double>> at_end = configuration_values(scene.observe.final_state, final, "");
    result.finals.insert(result.finals.begin(), at_end.begin(), at_end.end());  // first in final.json, as before
    for (const std::string& name : scene.observe.final_state) {
      const Observable observable = *Observable::from_name(name);
      if (observable.is_profile()) result.profiles.emplace_back(name, observable.profile(final));
    }
    for (auto& entry : simulation->final_values()) result.finals.push_back(std::move(entry));
    const double drift = norm(simulation->momentum() + simulation->wall_impulse() - p0);
    result.finals.emplace_back("wall_seconds", wall);
    result.finals.emplace_back("momentum_drift", momentum_scale > 0 ? drift / momentum_scale : drift);
    result.finals.emplace_back("stop_time", simulation->time());
    result.counters = simulation->counters();
    if (r == 0 && observer.final_configuration) observer.final_configuration(final);
    if (r == 0 && scene.observe.frame_every > 0) {
      std::vector<double> times{0.0};
      for (std::size_t k : scene.observe.frame_outputs) times.push_back(outputs[k]);
      write_trajectory_collection(observer.folder, times);
    }
    if (r == 0 && scene.observe.snapshots) {
      write_snapshot(observer.folder / "final.vtu", *simulation);
      std::string error;
      result.picture = write_cluster_picture(observer.folder / "final.png", final.configuration(), final.cluster_labels(), &error)
                           ? "final.png"
                           : "failed: " + error;
    }
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

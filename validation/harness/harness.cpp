#include "validation/harness/harness.hpp"

#include <algorithm>
#include <chrono>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "analysis/input_error.hpp"
#include "analysis/text.hpp"
#include "validation/harness/engine_record.hpp"
#include "validation/io/atomic_file.hpp"
#include "validation/harness/output_folder.hpp"
#include "validation/harness/run_checkpoint.hpp"
#include "validation/io/stop_signal.hpp"
#include "validation/harness/plot.hpp"
#include "validation/harness/recording_observer.hpp"
#include "validation/io/progress.hpp"
#include "validation/harness/report.hpp"
#include "validation/harness/series_output.hpp"
#include "validation/harness/summary.hpp"

namespace aggkit {

namespace {

// What rank 0 tells the other ranks (serve_realizations): run the share of an engine, or end.
const std::string engine_command = "engine ";
const std::string end_command = "end ";

// Runs one engine into a record; InputError propagates (bad input), any other failure is recorded.
EngineRecord run_engine(const Scene& scene, const Engine& engine, Progress& progress, const OutputFolder& folder,
                        RunCheckpoints* checkpoints, const RankGroup* ranks) {
  EngineRecord record;
  record.label = engine.label();
  record.name = engine.name();
  record.description = engine.describe();
  std::mutex record_lock;  // a checkpoint copies the record from the thread that saves
  std::unique_ptr<EngineCheckpoint> checkpoint;
  if (checkpoints) checkpoint = checkpoints->start(engine, record, record_lock);
  const double earlier_wall = record.wall_seconds;  // of the runs before a resume
  const auto started = std::chrono::steady_clock::now();
  EngineObserver observer = recording_observer(scene, record, record_lock,
                                               {[&progress](double t) { progress.reached(t); },
                                                [&progress](const std::string& what) { progress.note(what); }});
  observer.checkpoint = checkpoint.get();
  observer.folder = folder.engine_folder(engine.label());
  if (ranks && engine.spreads_over_ranks()) {  // the other ranks start their share (serve_realizations)
    ranks->broadcast(engine_command + engine.label());
    observer.ranks = ranks;
  }
  try {
    record.statistics = engine.run(scene, observer);
    if (record.times.size() != scene.time.outputs.size())
      throw std::runtime_error("the engine reported " + std::to_string(record.times.size()) + " of " +
                               std::to_string(scene.time.outputs.size()) + " output times");
    record_series_measures(record, scene);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    record.failure = e.what();
  }
  record.wall_seconds = earlier_wall + std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return record;
}

void write_engine_outputs(const Scene& scene, const EngineRecord& record, const OutputFolder& folder) {
  write_series_csv(folder.series_file(record.label), scene.observe, record);
  if (!scene.observe.distribution_times.empty()) write_distribution_csv(folder.distribution_file(record.label), record, scene.model.grid);
}

// Checkpoints hold every realization's state in one file written by one process: with the realizations on
// several ranks there is none, so a run that asks for them is refused before anything runs.
void refuse_checkpoints(const Scene& scene, const std::vector<std::unique_ptr<Engine>>& engines, const RunOptions& options) {
  const std::string allowed = "checkpoints with one process only: under mpirun with more than one rank the "
                              "realizations are spread over the ranks and no checkpoint is written (run with one "
                              "process to checkpoint or resume, or leave checkpoints out)";
  if (options.resume) throw InputError("--resume", options.out.string(), allowed);
  if (options.checkpoint_every > 0) throw InputError("--checkpoint-every", shortest_text(options.checkpoint_every), allowed);
  for (std::size_t i = 0; i < engines.size(); ++i) {
    const auto it = engines[i]->settings().find("checkpoint_every");
    if (it != engines[i]->settings().end() && it->is_number() && it->get<double>() > 0) {
      const EngineSpec* spec = nullptr;
      for (const EngineSpec& s : scene.engines)
        if (s.label == engines[i]->label()) spec = &s;
      throw InputError((spec ? spec->key : "engine[" + std::to_string(i) + "]") + ".checkpoint_every",
                       shortest_text(it->get<double>()), allowed);
    }
  }
}

}  // namespace

int serve_realizations(const Scene& scene, const RankGroup& ranks) {
  for (;;) {
    const std::string command = ranks.broadcast("");
    if (command.rfind(end_command, 0) == 0) return std::stoi(command.substr(end_command.size()));
    const std::string label = command.substr(engine_command.size());
    try {
      std::size_t index = 0;
      while (index < scene.engines.size() && scene.engines[index].label != label) ++index;
      if (index == scene.engines.size()) throw std::runtime_error("rank 0 runs engine " + label + ", which this rank's scene lacks");
      const std::unique_ptr<Engine> engine = build_engine(scene, index);
      EngineObserver observer;
      observer.measure = [&scene](double t, const ObservedState& state) { return measure_state(scene, t, state); };
      observer.ranks = &ranks;
      engine->run(scene, observer);
    } catch (const ShareAbandoned&) {
      // rank 0 reports the failure
    } catch (...) {
      // Failed before its first share (the engine could not be built here): it fails on every rank.
      const std::exception_ptr failure = std::current_exception();
      try {
        gather_shares(&ranks, [&]() -> std::string { std::rethrow_exception(failure); });
      } catch (const ShareAbandoned&) {
      }
    }
  }
}

void end_realization_service(const RankGroup& ranks, int exit_code) { ranks.broadcast(end_command + std::to_string(exit_code)); }

RunResult run_scene(const Scene& scene, const RunOptions& options) {
  return run_engines(scene, build_engines(scene), options);  // bad input fails before any output
}

namespace {

// The output folder prepared (a fresh run) and the checkpoints opened: when the run or an engine asks for
// them, or to resume.
void prepare_run(const Scene& scene, const std::vector<std::unique_ptr<Engine>>& engines, const RunOptions& options,
                 const OutputFolder& folder, const RankGroup* ranks, std::optional<RunCheckpoints>& checkpoints) {
  std::vector<std::pair<std::string, std::vector<std::string>>> files;
  for (const auto& engine : engines) {
    const EngineType* type = find_engine_type(engine->name());
    files.emplace_back(engine->label(), type ? type->files : std::vector<std::string>{});
  }
  // Checkpoints when the run or an engine asks for them; a resume keeps the outputs of the engines that
  // completed (and the trajectory files written so far).
  const bool engine_checkpoints = std::any_of(engines.begin(), engines.end(), [](const auto& engine) {
    const auto it = engine->settings().find("checkpoint_every");
    return it != engine->settings().end() && it->is_number() && it->template get<double>() > 0;
  });
  if (ranks) refuse_checkpoints(scene, engines, options);
  if (options.resume) {
    checkpoints.emplace(options.out, CheckpointedRun{options.scene_file, options.scene_fingerprint, options.checkpoint_every, options.plot},
                        true);
  } else {
    folder.prepare(files, options.force);
    if (options.checkpoint_every > 0 || engine_checkpoints)
      checkpoints.emplace(options.out, CheckpointedRun{options.scene_file, options.scene_fingerprint, options.checkpoint_every, options.plot},
                          false);
  }
  if (checkpoints && options.catch_signals) catch_stop_signals();
}

}  // namespace

RunResult run_engines(const Scene& scene, const std::vector<std::unique_ptr<Engine>>& engines, const RunOptions& options) {
  const OutputFolder folder(options.out);
  const RankGroup* ranks = shared_ranks(options.ranks);
  std::optional<RunCheckpoints> checkpoints;
  prepare_run(scene, engines, options, folder, ranks, checkpoints);

  // The plotter's interpreter starts now: its matplotlib import overlaps the engines.
  std::optional<SeriesPlotter> plotter;
  if (options.plot) plotter.emplace();
  RunResult result;
  Progress progress(options.progress, options.progress_interval);
  for (std::size_t i = 0; i < engines.size(); ++i) {
    const Engine& engine = *engines[i];
    if (checkpoints)
      if (std::optional<EngineRecord> done = checkpoints->completed(engine)) {  // resumed: its outputs are written
        result.records.push_back(std::move(*done));
        continue;
      }
    progress.start(engine.label(), i + 1, engines.size(), scene.time.end);
    try {
      result.records.push_back(run_engine(scene, engine, progress, folder, checkpoints ? &*checkpoints : nullptr, ranks));
    } catch (const RunInterrupted&) {
      progress.finish();
      throw;
    }
    progress.finish();
    if (options.warnings)
      for (const std::string& warning : result.records.back().warnings)
        *options.warnings << "aggkit: warning: engine " << engine.label() << ": " << warning << "\n";
    if (result.records.back().completed()) {
      write_engine_outputs(scene, result.records.back(), folder);
      if (checkpoints) {
        checkpoints->complete(engine, result.records.back());
        // A signal during an engine that saves no state of its own (snes, exact): its record is the checkpoint.
        if (options.catch_signals && stop_signal() != 0) throw RunInterrupted{stop_signal()};
      }
    } else if (options.warnings)
      *options.warnings << "aggkit: warning: engine " << engine.label() << " failed: " << *result.records.back().failure
                        << "\n";
  }

  if (scene.compare) result.comparisons = compare_engines(*scene.compare, scene.observe, result.records);
  result.pass = std::all_of(result.records.begin(), result.records.end(), [](const auto& r) { return r.completed(); }) &&
                std::all_of(result.comparisons.begin(), result.comparisons.end(), [](const auto& c) { return c.pass; });
  result.exit_code = result.pass ? exit_pass : exit_failed;

  if (options.plot) {
    result.plot = plotter->plot(scene, result.records, folder);
    if (result.plot.status == PlotOutcome::Status::failed && options.warnings)
      *options.warnings << "aggkit: warning: no plot: " << result.plot.message << "\n";
  } else {
    result.plot = {PlotOutcome::Status::skipped, "--no-plot"};
  }

  write_file_atomically(folder.summary_file(), summary_json(scene, result, folder));  // last: marks completion
  std::vector<std::string> labels;
  for (const auto& engine : engines) labels.push_back(engine->label());
  folder.mark(labels);
  if (checkpoints) checkpoints->finish();
  if (checkpoints && options.catch_signals) release_stop_signals();
  if (options.report) print_report(*options.report, scene, result, folder);
  return result;
}

}  // namespace aggkit

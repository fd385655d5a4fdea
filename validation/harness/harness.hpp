#pragma once
// The validation harness: `aggkit run SCENE --out DIR` .
//   1. checks that DIR can be written and removes stale outputs (else InputError, before anything runs);
//   2. runs each engine in scene order, writing DIR/<label>/series.csv (and distribution.csv) as each
//      one finishes; an engine that fails is recorded and the others still run;
//      (under `mpirun -np K`, with RunOptions::ranks, the realizations of particle and DSMC engines are
//      spread over the ranks, and only rank 0 writes: rank_share.hpp);
//   3. compares every engine with the reference, plots DIR/report.png, writes DIR/summary.json last
//      and prints a short summary.
// Every file is written under a temporary name and renamed when complete.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <iostream>

#include "validation/engines/engine.hpp"
#include "validation/engines/rank_share.hpp"
#include "validation/harness/run_result.hpp"
#include "validation/scene/scene.hpp"

namespace aggkit {

struct RunOptions {
  std::filesystem::path out;
  bool plot = true;
  bool force = false;                   // write into a non-empty folder aggkit did not write (OutputFolder)
  std::ostream* report = &std::cout;    // the human summary; nullptr: none
  std::ostream* progress = &std::cerr;  // progress of long runs; nullptr: quiet
  std::chrono::duration<double> progress_interval = std::chrono::seconds(1);  // at most one line per interval
  std::ostream* warnings = &std::cerr;  // e.g. a failed plot; nullptr: none
  // Checkpoints (run_checkpoint.hpp): wall seconds between them (--checkpoint-every; 0: each engine's own
  // option checkpoint_every, if it has one), whether to continue from DIR/checkpoint/, and the scene file and
  // its fingerprint that run.json records and a resume checks.
  double checkpoint_every = 0;
  bool resume = false;
  std::filesystem::path scene_file;
  std::uint64_t scene_fingerprint = 0;
  // SIGTERM and SIGINT write a last checkpoint and end the run (RunInterrupted) while checkpoints are on.
  bool catch_signals = false;
  // The ranks of `mpirun -np K aggkit run` (rank_share.hpp), on rank 0: the engines that spread their
  // realizations (particle engines, dsmc) run them on every rank, the others run here; every output is
  // written here. The other ranks run serve_realizations. Checkpoints are refused with more than one rank.
  // Unset: this process runs everything.
  const RankGroup* ranks = nullptr;
};

// Throws InputError for an unusable output folder or checkpoint, RunInterrupted after the last checkpoint of a
// run stopped by a signal, InputError or input an engine finds bad only when it runs; the
// exit code of the run (0 pass, 1 a comparison or an engine failed) is in the result.
RunResult run_scene(const Scene& scene, const RunOptions& options);
// The same with engines built already (build_engines(scene), or engines of a research code's own).
RunResult run_engines(const Scene& scene, const std::vector<std::unique_ptr<Engine>>& engines, const RunOptions& options);

// The ranks other than 0 of `mpirun -np K aggkit run`, while rank 0 runs run_scene(scene, options with
// `ranks`): runs this rank's share of each engine that rank 0 starts (building it from the scene), records
// and writes nothing, and returns the exit status rank 0 ends with (end_realization_service).
int serve_realizations(const Scene& scene, const RankGroup& ranks);
// On rank 0, once run_scene has returned or thrown: ends serve_realizations on the other ranks with
// `exit_code`. Must be called exactly once, whatever happened, so that no rank is left waiting.
void end_realization_service(const RankGroup& ranks, int exit_code);

}  // namespace aggkit

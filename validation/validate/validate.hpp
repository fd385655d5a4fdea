#pragma once
// `aggkit validate [--tier fast|full] [--out DIR] [--jobs K] [SCENE ...]`: runs the scenes of a validation
// plan (validation_plan.hpp), each in a child process of the aggkit program (`aggkit run SCENE --out
// DIR/<scene>` or `aggkit scan ...` for a scan scene), K at a time, with its output in DIR/logs/<scene>.log.
// Each scene holds job slots (cores) while it runs, K in all (job_slots.hpp): scan scenes start first, and
// each takes every free slot it can use, running as `mpiexec -np S aggkit scan ...` when it holds S > 1 (its
// ranks draw the points from a shared counter, and a point's result does not depend on the rank that ran it,
// so the outputs are those of one process); then the full-tier scenes, then the fast ones, one slot each.
// Why this order and not a scan that grows as slots free up: an MPI job cannot take ranks while it runs, and
// the work is the same either way — started first with all K slots a scan keeps them busy until it ends, and
// the short scenes after it fill the cores to the end, where a scan started beside them would be left alone
// on one core at the end. Without an MPI launcher (ValidateOptions::mpiexec empty) every scene holds one slot.
// A scene that finishes with a verdict is recorded in DIR/finished/ (finished_record.hpp): a validation that
// is interrupted (Ctrl-C, a kill; its running scenes are ended with it) and started again with the same DIR
// reruns only the scenes not finished. Then it prints the pass/fail table, and writes DIR/validation.json
// and DIR/report.html (atomically).
// Exit status: 0 every scene passes; 1 a scene failed (a comparison, an engine, a crash); 2 bad input
// (found before anything runs — option, scene file, output folder — or by a scene's own run).
// MPI: `aggkit validate` runs its scenes as child processes and refuses to run under mpirun. On a cluster a
// scene's realizations are spread over ranks by running it alone: `mpirun -np K aggkit run SCENE --out DIR`
// (README, examples/slurm-run.sh).
#include <cstddef>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "validation/validate/scene_outcome.hpp"

namespace aggkit {

struct ValidateOptions {
  std::filesystem::path out = "validation";
  SceneTier tier = SceneTier::fast;
  std::vector<std::string> scenes;  // SCENE arguments; empty: the shipped scenes
  std::size_t jobs = 1;             // child processes at a time
  bool plot = true;                 // false: --no-plot for every scene
  bool rerun = false;               // forget the finished scenes of an earlier validation into `out`
  std::filesystem::path program;    // the aggkit executable that runs each scene
  std::filesystem::path mpiexec;    // starts a scan scene on several slots; empty: every scene on one slot
  std::ostream* progress = nullptr; // progress lines; nullptr: quiet
  std::ostream* table = nullptr;    // the pass/fail table; nullptr: none
};

struct ValidationOutcome {
  std::vector<SceneOutcome> scenes;
  int exit_code = 0;
};

// InputError for bad options, scenes or output folder, before any scene runs (key AGGKIT_MPIEXEC for an
// `mpiexec` that is not an executable file).
ValidationOutcome run_validation(const ValidateOptions& options);

// The MPI launcher for ValidateOptions::mpiexec: $AGGKIT_MPIEXEC if it is set (empty: none), else the mpiexec
// aggkit was built with if it is there, else none.
std::filesystem::path default_mpiexec();

}  // namespace aggkit

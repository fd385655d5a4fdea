#pragma once
// `aggkit validate [--tier fast|full] [--out DIR] [--jobs K] [SCENE ...]`: runs the scenes of a validation
// plan (validation_plan.hpp), each in a child process of the aggkit program (`aggkit run SCENE --out
// DIR/<scene>` or `aggkit scan ...` for a scan scene), K at a time, with its output in DIR/logs/<scene>.log.
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
  std::ostream* progress = nullptr; // progress lines; nullptr: quiet
  std::ostream* table = nullptr;    // the pass/fail table; nullptr: none
};

struct ValidationOutcome {
  std::vector<SceneOutcome> scenes;
  int exit_code = 0;
};

// InputError for bad options, scenes or output folder, before any scene runs.
ValidationOutcome run_validation(const ValidateOptions& options);

}  // namespace aggkit

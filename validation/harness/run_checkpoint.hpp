#pragma once
// The checkpoints of a run (`aggkit run SCENE --out DIR --checkpoint-every 10m`, `aggkit run --resume DIR`),
// in DIR/checkpoint/:
//   run.json       the scene file, its fingerprint (FNV-1a of its text) and the run's options: what --resume
//                  needs to start the same run again;
//   <label>.state  per engine, a checkpoint file (particle/common/checkpoint.hpp: versioned header naming
//                  aggkit's version, the engine and the scene fingerprint; length and checksum) whose payload
//                  is what the harness has recorded of the engine (the series so far, or everything when it
//                  completed) followed by the engine's own state (EngineCheckpoint).
// A finished run removes the folder. A checkpoint that fails any check is refused (InputError for --resume:
// exit status 2), never half-read.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "validation/harness/engine_record.hpp"
#include "validation/runs/fingerprint.hpp"  // scene_fingerprint, the fingerprint run.json records

namespace aggkit {

// What run.json holds.
struct CheckpointedRun {
  std::filesystem::path scene;      // absolute
  std::uint64_t fingerprint = 0;    // of the scene's text when the run started
  double interval = 0;              // --checkpoint-every, seconds (0: the engines' own checkpoint_every)
  bool plot = true;
};

// run.json of DIR; InputError for --resume when there is none or it cannot be read.
CheckpointedRun read_checkpointed_run(const std::filesystem::path& out);

class RunCheckpoints {
 public:
  // `resume`: continue from DIR/checkpoint/ (its run.json must exist); else a fresh run, whose earlier
  // checkpoints are removed. Writes run.json when `run.interval` > 0 or an engine asks for checkpoints.
  RunCheckpoints(const std::filesystem::path& out, CheckpointedRun run, bool resume);
  bool resuming() const { return resume_; }
  std::filesystem::path folder() const { return folder_; }

  // When resuming: the record of an engine that had completed, if it had.
  std::optional<EngineRecord> completed(const Engine& engine) const;
  // The engine's checkpoint for a run of it: restores `record` to what had been recorded when resuming, and
  // saves into <label>.state. `interval` is the engine's own checkpoint_every when the run gives none.
  std::unique_ptr<EngineCheckpoint> start(const Engine& engine, EngineRecord& record, std::mutex& record_lock);
  // Records the engine as completed (after its outputs are written).
  void complete(const Engine& engine, const EngineRecord& record) const;
  // The run finished: removes DIR/checkpoint/.
  void finish() const;

 private:
  std::filesystem::path folder_;
  CheckpointedRun run_;
  bool resume_;
};

}  // namespace aggkit

#pragma once
// DIR/finished/<folder>.json: a scene of a validation has finished with a verdict (exit 0 or 1), written
// atomically when its child process ends, so that an interrupted validation resumes without rerunning it.
// A record is reused only while the scene's fingerprint (its file's text, how it is run) is unchanged.
// Scenes that ended without a verdict (bad input, an internal error, a signal) are not recorded: a rerun
// tries them again.
#include <filesystem>
#include <optional>
#include <string>

#include "validation/validate/validation_plan.hpp"

namespace aggkit {

struct FinishedRecord {
  int exit_code = 0;
  double wall_seconds = 0;  // the child process, plots included
};

std::filesystem::path finished_folder(const std::filesystem::path& out);
void write_finished_record(const std::filesystem::path& out, const PlannedScene& scene, const FinishedRecord& record);
// The record of `scene` if there is one of its current fingerprint.
std::optional<FinishedRecord> read_finished_record(const std::filesystem::path& out, const PlannedScene& scene);
void forget_finished_record(const std::filesystem::path& out, const PlannedScene& scene);

}  // namespace aggkit

#include "validation/validate/finished_record.hpp"

#include <system_error>

#include <nlohmann/json.hpp>

#include "validation/io/atomic_file.hpp"
#include "validation/runs/json_record.hpp"
#include "validation/runs/run_store.hpp"

namespace aggkit {

namespace {

std::filesystem::path record_file(const std::filesystem::path& out, const PlannedScene& scene) {
  return finished_folder(out) / (scene.folder + ".json");
}

}  // namespace

std::filesystem::path finished_folder(const std::filesystem::path& out) { return out / "finished"; }

void write_finished_record(const std::filesystem::path& out, const PlannedScene& scene, const FinishedRecord& record) {
  const nlohmann::ordered_json json = {{"scene", scene.name},
                                       {"file", scene.file.string()},
                                       {"fingerprint", scene.fingerprint},
                                       {"exit_code", record.exit_code},
                                       {"wall_seconds", record.wall_seconds}};
  write_file_atomically(record_file(out, scene), json.dump(2) + "\n");
}

std::optional<FinishedRecord> read_finished_record(const std::filesystem::path& out, const PlannedScene& scene) {
  const std::optional<nlohmann::json> text = json_record(read_text_file(record_file(out, scene)));
  if (!text) return std::nullopt;
  const nlohmann::json& json = *text;
  // Every field is type-checked before it is read: a damaged record is no record (the scene runs again),
  // never a type error.
  if (!json.contains("fingerprint") || !json["fingerprint"].is_string() ||
      json["fingerprint"].get<std::string>() != scene.fingerprint || !json.contains("exit_code") ||
      !json["exit_code"].is_number_integer() || !json.contains("wall_seconds") || !json["wall_seconds"].is_number())
    return std::nullopt;
  FinishedRecord record{json["exit_code"].get<int>(), json["wall_seconds"].get<double>()};
  if (record.exit_code != 0 && record.exit_code != 1) return std::nullopt;
  return record;
}

void forget_finished_record(const std::filesystem::path& out, const PlannedScene& scene) {
  std::error_code error;
  std::filesystem::remove(record_file(out, scene), error);
}

}  // namespace aggkit

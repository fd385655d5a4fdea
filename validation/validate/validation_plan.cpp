#include "validation/validate/validation_plan.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <system_error>

#include "analysis/input_error.hpp"
#include "validation/runs/fingerprint.hpp"
#include "validation/scan/scan_plan.hpp"
#include "validation/scene/scene_table.hpp"

namespace aggkit {

namespace {

// The scene's name as a folder name: characters other than letters, digits, '.', '-' and '_' become '_', and
// a leading '.' too (no hidden folders, no "..").
std::string folder_name(const std::string& name) {
  std::string folder = name;
  for (char& c : folder) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                       c == '-' || c == '_';
    if (!plain) c = '_';
  }
  if (!folder.empty() && folder.front() == '.') folder.front() = '_';
  return folder;
}

std::vector<std::filesystem::path> scene_files_in(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> files;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error))
    if (entry.path().extension() == ".toml" && entry.is_regular_file(error)) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

PlannedScene read_planned(const std::filesystem::path& file, bool plot) {
  const std::string text = read_scene_file(file);
  const toml::table document = parse_toml_text(text, file.string());
  PlannedScene planned;
  planned.file = file;
  planned.kind = document.contains("scan") ? SceneKind::scan : SceneKind::run;
  Scene scene;
  if (planned.kind == SceneKind::scan) {
    ScanPlan scan = load_scan_plan(file);
    planned.runs = scan.point_count() + 2 * scan.check_points.size();
    scene = std::move(scan.scene);
  } else {
    scene = load_scene(file);
  }
  planned.name = scene.name;
  planned.folder = folder_name(scene.name);
  planned.tier = scene.tier;
  for (const auto& engine : scene.engines) planned.engines.push_back(engine.label);
  planned.description = opening_comment(text);
  planned.fingerprint = fingerprint_text(text_fingerprint(text + "\n# aggkit validate: " + to_string(planned.kind) + (plot ? " plot" : " no-plot")));
  return planned;
}

}  // namespace

const char* to_string(SceneKind kind) { return kind == SceneKind::scan ? "scan" : "run"; }

SceneTier parse_tier(const std::string& text) {
  if (text == "fast") return SceneTier::fast;
  if (text == "full") return SceneTier::full;
  throw InputError("--tier", text, "fast (the scenes of tier fast) or full (every scene)");
}

std::filesystem::path shipped_scene_folder() {
  if (const char* folder = std::getenv("AGGKIT_SCENES"); folder && *folder) return folder;
  std::error_code error;
  if (std::filesystem::is_directory(AGGKIT_SCENES_BUILD, error)) return AGGKIT_SCENES_BUILD;
  return AGGKIT_SCENES_INSTALL;
}

std::string opening_comment(const std::string& text) {
  std::string comment;
  std::size_t begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(begin, end - begin);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    begin = end + 1;
    if (line.empty() && comment.empty()) continue;
    if (line.empty() || line.front() != '#') break;
    line.erase(0, 1);
    if (!line.empty() && line.front() == ' ') line.erase(0, 1);
    comment += line + "\n";
  }
  while (!comment.empty() && comment.back() == '\n') comment.pop_back();
  return comment;
}

ValidationPlan plan_validation(const std::vector<std::string>& arguments, SceneTier tier, bool plot) {
  ValidationPlan plan;
  plan.tier = tier;
  // (file, filtered by tier)
  std::vector<std::pair<std::filesystem::path, bool>> files;
  const auto add_folder = [&](const std::filesystem::path& folder, const std::string& argument) {
    const auto found = scene_files_in(folder);
    if (found.empty()) throw InputError("SCENE", argument, "a folder holding scene files (*.toml); it has none");
    for (const auto& file : found) files.emplace_back(file, true);
  };
  if (arguments.empty()) {
    const std::filesystem::path shipped = shipped_scene_folder();
    std::error_code error;
    if (!std::filesystem::is_directory(shipped, error))
      throw InputError("SCENE", "(none: the shipped scenes)", "the folder of shipped scenes " + shipped.string() +
                                                                  ", which does not exist (set AGGKIT_SCENES)");
    add_folder(shipped, shipped.string());
  }
  for (const std::string& argument : arguments) {
    std::error_code error;
    const std::filesystem::path path(argument);
    if (std::filesystem::is_directory(path, error)) {
      add_folder(path, argument);
    } else if (std::filesystem::exists(path, error)) {
      files.emplace_back(path, false);
    } else if (const auto shipped = shipped_scene_folder() / (argument + ".toml");
               argument.find('/') == std::string::npos && std::filesystem::is_regular_file(shipped, error)) {
      files.emplace_back(shipped, false);
    } else {
      std::vector<std::string> names;
      for (const auto& file : scene_files_in(shipped_scene_folder())) names.push_back(file.stem().string());
      throw InputError("SCENE", argument,
                       "a scene file, a folder of scene files or the name of a shipped scene (" + join(names) + ")");
    }
  }
  std::map<std::string, std::filesystem::path> folders{{"logs", ""}, {"finished", ""}};  // the validation's own
  for (const auto& [file, filtered] : files) {
    PlannedScene planned = read_planned(file, plot);
    if (filtered && tier == SceneTier::fast && planned.tier == SceneTier::full) {
      plan.notes.push_back(planned.name + " (" + file.string() + "): tier full, left out under --tier fast");
      continue;
    }
    const auto [existing, inserted] = folders.emplace(planned.folder, file);
    if (!inserted)
      throw InputError(file.string() + ": name", planned.name,
                       "a name whose folder " + planned.folder + " is not taken by " +
                           (existing->second.empty() ? std::string("the validation's own files")
                                                     : existing->second.string()) +
                           " (each scene of a validation needs its own output folder)");
    plan.scenes.push_back(std::move(planned));
  }
  return plan;
}

}  // namespace aggkit

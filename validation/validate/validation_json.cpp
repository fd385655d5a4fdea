#include "validation/validate/validation_json.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "validation/io/version.hpp"

namespace aggkit {

namespace {

using Json = nlohmann::ordered_json;

Json number(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }

Json comparison_json(const ComparisonLine& c) {
  Json json = {{"engine", c.engine},
               {"reference", c.reference},
               {"observable", c.observable},
               {"kind", c.kind},
               {"max_relative_error", number(c.error)},
               {"time", number(c.time)},
               {"tolerance", c.tolerance ? Json(*c.tolerance) : Json(nullptr)}};
  if (c.tolerance_stderr) json["tolerance_stderr"] = *c.tolerance_stderr;
  if (!std::isnan(c.error_in_stderr)) json["max_error_in_stderr"] = number(c.error_in_stderr);
  json["tolerance_used"] = number(c.tolerance_used);
  json["pass"] = c.pass ? Json(*c.pass) : Json(nullptr);
  return json;
}

Json scene_json(const SceneOutcome& s) {
  Json json = {{"name", s.scene.name},
               {"folder", s.scene.folder},
               {"file", s.scene.file.string()},
               {"kind", to_string(s.scene.kind)},
               {"tier", to_string(s.scene.tier)},
               {"engines", s.scene.engines},
               {"result", to_string(s.verdict)},
               {"exit_code", s.exit_code >= 0 ? Json(s.exit_code) : Json(nullptr)}};
  if (s.signal) json["signal"] = s.signal;
  json["resumed"] = s.resumed;
  json["wall_seconds"] = number(s.wall_seconds);
  if (!s.problem.empty()) json["problem"] = s.problem;
  if (s.scene.kind == SceneKind::scan) json["scan_points"] = s.scan_points;
  json["worst"] = s.worst ? comparison_json(s.comparisons[*s.worst]) : Json(nullptr);
  std::size_t failed = 0;
  for (const auto& c : s.comparisons) failed += c.pass == false ? 1 : 0;
  json["comparisons"] = s.comparisons.size();
  json["failed_comparisons"] = failed;
  if (s.scene.kind == SceneKind::run) json["summary"] = s.scene.folder + "/summary.json";
  json["log"] = "logs/" + s.scene.folder + ".log";
  json["images"] = s.images;
  return json;
}

}  // namespace

std::string validation_json(const std::vector<SceneOutcome>& scenes, const ValidationTotals& totals) {
  // no_check: scenes that ran without a check (Verdict::unchecked), counted apart from pass.
  Json counts = {{"scenes", scenes.size()}, {"pass", 0}, {"fail", 0}, {"bad_input", 0}, {"error", 0},
                 {"not_run", 0},           {"no_check", 0}, {"resumed", 0}};
  for (const auto& s : scenes) {
    const char* key = count_key(s.verdict);
    counts[key] = counts[key].get<int>() + 1;
    if (s.resumed) counts["resumed"] = counts["resumed"].get<int>() + 1;
  }
  Json json = {{"aggkit_version", version()},
               {"tier", to_string(totals.tier)},
               {"jobs", totals.jobs},
               {"wall_seconds", number(totals.wall_seconds)},
               {"pass", totals.exit_code == 0},
               {"exit_code", totals.exit_code},
               {"counts", counts},
               {"notes", totals.notes},
               {"scenes", Json::array()}};
  for (const auto& s : scenes) json["scenes"].push_back(scene_json(s));
  return json.dump(2) + "\n";
}

}  // namespace aggkit

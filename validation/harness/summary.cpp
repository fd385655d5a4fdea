#include "validation/harness/summary.hpp"

#include <cmath>
#include <type_traits>
#include <variant>

#include <nlohmann/json.hpp>

#include "validation/io/version.hpp"

namespace aggkit {

namespace {

using Json = nlohmann::ordered_json;

Json number(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }

std::string relative(const std::filesystem::path& file, const OutputFolder& folder) {
  return file.lexically_relative(folder.root()).generic_string();
}

Json scene_json(const Scene& scene) {
  Json json = {
      {"name", scene.name},
      {"path", scene.path.string()},
      {"absolute_path", scene.path.empty() ? std::string() : std::filesystem::absolute(scene.path).string()},
  };
  if (scene.has_model) {
    const AggregationModel& m = scene.model;
    Json kernel_parameters = Json::object();
    for (const auto& [name, value] : m.kernel.parameters()) kernel_parameters[name] = value;
    json["model"] = {{"kernel", m.kernel.name()},
                     {"kernel_parameters", kernel_parameters},
                     {"lambda", m.lambda.describe()},
                     {"size", m.size},
                     {"truncation", to_string(m.truncation)},
                     {"initial", scene.initial.kind == InitialCondition::Kind::monodisperse ? "monodisperse" : "table"}};
  }
  if (scene.particles) {
    const ParticleSystem& p = *scene.particles;
    json["particles"] = {{"dimension", p.box.dimension},
                         {"count", p.count},
                         {"radius", p.mean_radius()},
                         {"volume_fraction", p.volume_fraction()},
                         {"boundary", to_string(p.box.boundary)},
                         {"realizations", p.realizations}};
  }
  json["time"] = {{"end", scene.time.end}, {"outputs", scene.time.outputs.size()}};
  return json;
}

Json engine_json(const EngineRecord& record, const OutputFolder& folder) {
  Json statistics = Json::object();
  for (const auto& s : record.statistics)
    std::visit([&](const auto& v) {
      if constexpr (std::is_same_v<std::decay_t<decltype(v)>, double>)
        statistics[s.name] = number(v);
      else
        statistics[s.name] = v;
    }, s.value);
  Json engine = {{"name", record.name}, {"description", record.description},
                 {"status", record.completed() ? "completed" : "failed"}};
  if (record.failure) engine["error"] = *record.failure;
  if (!record.warnings.empty()) engine["warnings"] = record.warnings;
  engine["wall_seconds"] = number(record.wall_seconds);
  engine["outputs_reached"] = record.times.size();
  engine["final_mass_leak"] = number(record.final_mass_leak);
  if (record.completed()) {
    engine["files"] = {{"series", relative(folder.series_file(record.label), folder)}};
    if (!record.distributions.empty())
      engine["files"]["distribution"] = relative(folder.distribution_file(record.label), folder);
  }
  engine["statistics"] = statistics;
  if (!record.finals.empty()) {  // final.json of a particle engine and the series measures
    Json finals = Json::object();
    for (const auto& f : record.finals) {
      finals[f.name] = number(f.mean);
      finals[f.name + "_stderr"] = number(f.standard_error);
    }
    engine["final"] = finals;
  }
  return engine;
}

Json comparison_json(const ComparisonResult& c) {
  Json json = {{"engine", c.engine},
               {"reference", c.reference},
               {"observable", c.observable},
               {"kind", c.final_state ? "final" : "series"},
               {"max_relative_error", number(c.max_relative_error)},
               {"time", number(c.time)},
               {"tolerance", c.tolerance ? Json(*c.tolerance) : Json(nullptr)},
               {"pass", c.tolerance ? Json(c.pass) : Json(nullptr)}};
  if (c.stderr_multiple) json["tolerance_stderr"] = *c.stderr_multiple;
  if (c.tolerance) json["tolerance_used"] = number(c.tolerance_used);
  if (!std::isnan(c.max_standard_errors)) json["max_error_in_stderr"] = number(c.max_standard_errors);
  if (!c.note.empty()) json["note"] = c.note;
  return json;
}

}  // namespace

std::string summary_json(const Scene& scene, const RunResult& result, const OutputFolder& folder) {
  Json summary;
  summary["aggkit_version"] = version();
  summary["scene"] = scene_json(scene);
  summary["engines"] = Json::object();
  for (const auto& record : result.records) summary["engines"][record.label] = engine_json(record, folder);
  summary["comparisons"] = Json::array();
  for (const auto& c : result.comparisons) summary["comparisons"].push_back(comparison_json(c));
  summary["plot"] = {{"status", to_string(result.plot.status)}};
  if (result.plot.status == PlotOutcome::Status::written)
    summary["plot"]["file"] = relative(folder.report_file(), folder);
  if (!result.plot.message.empty()) summary["plot"]["message"] = result.plot.message;
  summary["pass"] = result.pass;
  summary["exit_code"] = result.exit_code;
  return summary.dump(2) + "\n";
}

}  // namespace aggkit

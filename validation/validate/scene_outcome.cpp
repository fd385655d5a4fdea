#include "validation/validate/scene_outcome.hpp"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

#include <nlohmann/json.hpp>

namespace aggkit {

namespace {

using Json = nlohmann::json;

double number_or_nan(const Json& object, const char* key) {
  const auto it = object.find(key);
  return it != object.end() && it->is_number() ? it->get<double>() : ComparisonLine::nan;
}
std::optional<double> optional_number(const Json& object, const char* key) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number()) return std::nullopt;
  return it->get<double>();
}
std::string text_or_empty(const Json& object, const char* key) {
  const auto it = object.find(key);
  return it != object.end() && it->is_string() ? it->get<std::string>() : std::string();
}

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The last `lines` lines of a file (at most 4 kB of them).
std::string tail(const std::filesystem::path& file, std::size_t lines) {
  std::string text = read_text(file);
  if (text.size() > 4096) text.erase(0, text.size() - 4096);
  std::size_t at = text.size();
  while (!text.empty() && text.back() == '\n') text.pop_back(), at = text.size();
  for (std::size_t n = 0; n < lines && at != std::string::npos && at > 0; ++n) at = text.rfind('\n', at - 1);
  return at == std::string::npos ? text : text.substr(at + 1);
}

std::size_t data_rows(const std::filesystem::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::size_t rows = 0;
  while (std::getline(in, line))
    if (!line.empty()) ++rows;
  return rows > 0 ? rows - 1 : 0;
}

void read_summary(const std::filesystem::path& file, SceneOutcome& outcome) {
  std::ifstream in(file);
  const Json summary = Json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!summary.is_object()) {
    outcome.problem = "no readable summary.json";
    return;
  }
  if (const auto engines = summary.find("engines"); engines != summary.end() && engines->is_object())
    for (const auto& [label, engine] : engines->items()) {
      if (!engine.is_object()) continue;
      outcome.engines.push_back({label, text_or_empty(engine, "name"), text_or_empty(engine, "status"),
                                 number_or_nan(engine, "wall_seconds"), text_or_empty(engine, "error")});
    }
  if (const auto comparisons = summary.find("comparisons"); comparisons != summary.end() && comparisons->is_array())
    for (const auto& c : *comparisons) {
      if (!c.is_object()) continue;
      ComparisonLine line;
      line.engine = text_or_empty(c, "engine");
      line.reference = text_or_empty(c, "reference");
      line.observable = text_or_empty(c, "observable");
      line.kind = text_or_empty(c, "kind");
      line.error = number_or_nan(c, "max_relative_error");
      line.time = number_or_nan(c, "time");
      line.tolerance = optional_number(c, "tolerance");
      line.tolerance_stderr = optional_number(c, "tolerance_stderr");
      line.error_in_stderr = number_or_nan(c, "max_error_in_stderr");
      line.tolerance_used = number_or_nan(c, "tolerance_used");
      if (const auto pass = c.find("pass"); pass != c.end() && pass->is_boolean()) line.pass = pass->get<bool>();
      line.note = text_or_empty(c, "note");
      outcome.comparisons.push_back(std::move(line));
    }
}

std::vector<std::string> images_under(const std::filesystem::path& out, const std::filesystem::path& folder) {
  std::vector<std::string> images;
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error)) return images;
  for (auto it = std::filesystem::recursive_directory_iterator(folder, error);
       !error && it != std::filesystem::recursive_directory_iterator(); it.increment(error))
    if (it->path().extension() == ".png" && it->is_regular_file(error))
      images.push_back(it->path().lexically_relative(out).generic_string());
  // The scene's own plots (report.png, phase_diagram.png: directly in its folder) first, then the engines'.
  std::sort(images.begin(), images.end(), [](const std::string& a, const std::string& b) {
    const auto depth = [](const std::string& s) { return std::count(s.begin(), s.end(), '/'); };
    return depth(a) != depth(b) ? depth(a) < depth(b) : a < b;
  });
  return images;
}

}  // namespace

const char* to_string(Verdict verdict) {
  switch (verdict) {
    case Verdict::pass: return "pass";
    case Verdict::fail: return "FAIL";
    case Verdict::bad_input: return "bad input";
    case Verdict::error: return "error";
    case Verdict::not_run: return "not run";
    case Verdict::unchecked: return "ran (no check)";
  }
  return "?";
}

const char* count_key(Verdict verdict) {
  switch (verdict) {
    case Verdict::pass: return "pass";
    case Verdict::fail: return "fail";
    case Verdict::bad_input: return "bad_input";
    case Verdict::error: return "error";
    case Verdict::not_run: return "not_run";
    case Verdict::unchecked: return "no_check";
  }
  return "?";
}

bool without_failure(Verdict verdict) { return verdict == Verdict::pass || verdict == Verdict::unchecked; }

std::optional<std::size_t> worst_comparison(const std::vector<ComparisonLine>& comparisons) {
  std::optional<std::size_t> worst;
  // Rank: (has a tolerance, failed, share used (NaN highest), error (NaN highest)); larger is worse.
  const auto badness = [](double x) { return std::isnan(x) ? HUGE_VAL : x; };
  const auto worse = [&](const ComparisonLine& a, const ComparisonLine& b) {
    const bool ta = a.tolerance.has_value(), tb = b.tolerance.has_value();
    if (ta != tb) return ta;
    const bool fa = a.pass == false, fb = b.pass == false;
    if (fa != fb) return fa;
    if (ta && badness(a.tolerance_used) != badness(b.tolerance_used))
      return badness(a.tolerance_used) > badness(b.tolerance_used);
    return badness(a.error) > badness(b.error);
  };
  for (std::size_t i = 0; i < comparisons.size(); ++i)
    if (!worst || worse(comparisons[i], comparisons[*worst])) worst = i;
  return worst;
}

SceneOutcome read_scene_outcome(const std::filesystem::path& out, const PlannedScene& scene, int exit_code, int signal,
                                double wall_seconds, bool resumed) {
  SceneOutcome outcome;
  outcome.scene = scene;
  outcome.exit_code = exit_code;
  outcome.signal = signal;
  outcome.wall_seconds = wall_seconds;
  outcome.resumed = resumed;
  const std::filesystem::path folder = out / scene.folder;
  std::error_code error;
  if (scene.kind == SceneKind::run) {
    if (std::filesystem::exists(folder / "summary.json", error)) read_summary(folder / "summary.json", outcome);
    else if (exit_code == 0 || exit_code == 1) outcome.problem = "no summary.json";
    outcome.worst = worst_comparison(outcome.comparisons);
  } else {
    outcome.scan_points = data_rows(folder / "scan.csv");
    if (exit_code == 0 && !std::filesystem::exists(folder / "scan.csv", error)) outcome.problem = "no scan.csv";
  }
  outcome.images = images_under(out, folder);

  // A check: a comparison with a tolerance (pass true or false); comparisons without one are reported only.
  const bool checked = scene.kind == SceneKind::run &&
                       std::any_of(outcome.comparisons.begin(), outcome.comparisons.end(),
                                   [](const ComparisonLine& c) { return c.pass.has_value(); });
  if (exit_code == 0 && outcome.problem.empty()) outcome.verdict = checked ? Verdict::pass : Verdict::unchecked;
  else if (exit_code == 0 || exit_code == 1) outcome.verdict = Verdict::fail;
  else if (exit_code == 2) outcome.verdict = Verdict::bad_input;
  else outcome.verdict = Verdict::error;

  if (outcome.verdict == Verdict::unchecked)
    outcome.problem = scene.kind == SceneKind::scan ? "a scan: its points are classified, not checked"
                                                    : "no comparison with a tolerance ([compare])";
  if (!without_failure(outcome.verdict)) {
    if (outcome.problem.empty()) {
      if (exit_code == 1) {
        for (const auto& e : outcome.engines)
          if (e.status == "failed") outcome.problem = "engine " + e.label + " failed: " + e.error;
        if (outcome.problem.empty() && outcome.worst && outcome.comparisons[*outcome.worst].pass == false) {
          const ComparisonLine& c = outcome.comparisons[*outcome.worst];
          outcome.problem = c.engine + " " + c.observable + " is outside its tolerance";
        }
        if (outcome.problem.empty()) outcome.problem = scene.kind == SceneKind::scan ? "some scan points failed"
                                                                                     : "exit status 1";
      } else if (exit_code == 2) {
        outcome.problem = "bad input (exit status 2)";
      } else if (signal != 0) {
        outcome.problem = std::string("ended by signal ") + std::to_string(signal) + " (" + strsignal(signal) + ")";
      } else {
        outcome.problem = "exit status " + std::to_string(exit_code);
      }
    }
    outcome.log_tail = tail(out / "logs" / (scene.folder + ".log"), 12);
  }
  return outcome;
}

}  // namespace aggkit

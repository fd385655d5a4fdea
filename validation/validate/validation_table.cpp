#include "validation/validate/validation_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "validation/io/text.hpp"

namespace aggkit {

namespace {

std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

// Display width: the UTF-8 characters (σ, —) count once.
std::size_t width(const std::string& text) {
  std::size_t n = 0;
  for (const unsigned char c : text) n += (c & 0xC0) != 0x80 ? 1 : 0;
  return n;
}

}  // namespace

std::string seconds_text(double seconds) {
  if (std::isnan(seconds)) return "—";
  return format(seconds < 10 ? "%.1f" : "%.0f", seconds);
}

std::string error_text(const ComparisonLine& c) {
  if (std::isnan(c.error)) return "NaN";
  std::string text = format("%.2g", c.error);
  if (!std::isnan(c.error_in_stderr)) text += " (" + format("%.2g", c.error_in_stderr) + " σ)";
  return text;
}

std::string tolerance_text(const ComparisonLine& c) {
  if (!c.tolerance) return "none";
  std::string text = shortest_text(*c.tolerance);
  if (c.tolerance_stderr) text += " + " + shortest_text(*c.tolerance_stderr) + " σ";
  return text;
}

std::string used_text(const ComparisonLine& c) {
  if (!c.tolerance) return "—";
  if (std::isnan(c.tolerance_used)) return "NaN";
  return format(c.tolerance_used < 0.1 ? "%.2g %%" : "%.0f %%", 100 * c.tolerance_used);
}

std::string worst_text(const SceneOutcome& outcome) {
  if (outcome.scene.kind == SceneKind::scan) return std::to_string(outcome.scan_points) + " points classified";
  if (!outcome.worst)
    return outcome.verdict == Verdict::unchecked || outcome.verdict == Verdict::fail ? "no comparisons" : "—";
  const ComparisonLine& c = outcome.comparisons[*outcome.worst];
  return c.engine + " " + c.observable + (c.kind == "final" ? " (final)" : "") + " vs " + c.reference;
}

std::string engines_text(const SceneOutcome& outcome) {
  std::string text = join(outcome.scene.engines);
  if (outcome.scene.kind == SceneKind::scan) text += " (scan)";
  return text;
}

void print_validation_table(std::ostream& out, const std::vector<SceneOutcome>& scenes) {
  std::vector<std::vector<std::string>> rows{
      {"scene", "tier", "engines", "worst comparison", "error", "tolerance", "used", "wall s", "result"}};
  for (const auto& s : scenes) {
    const ComparisonLine* worst = s.worst ? &s.comparisons[*s.worst] : nullptr;
    rows.push_back({s.scene.name, to_string(s.scene.tier), engines_text(s), worst_text(s),
                    worst ? error_text(*worst) : "", worst ? tolerance_text(*worst) : "", worst ? used_text(*worst) : "",
                    seconds_text(s.wall_seconds) + (s.resumed ? "*" : ""), to_string(s.verdict)});
  }
  std::vector<std::size_t> widths(rows.front().size(), 0);
  for (const auto& row : rows)
    for (std::size_t j = 0; j < row.size(); ++j) widths[j] = std::max(widths[j], width(row[j]));
  for (const auto& row : rows) {
    std::string line;
    for (std::size_t j = 0; j < row.size(); ++j) {
      line += row[j];
      if (j + 1 < row.size()) line += std::string(widths[j] - width(row[j]) + 2, ' ');
    }
    out << line << "\n";
  }
  if (std::any_of(scenes.begin(), scenes.end(), [](const SceneOutcome& s) { return s.resumed; }))
    out << "* finished in an earlier run of aggkit validate into the same folder, not rerun\n";
  for (const auto& s : scenes)
    if (s.verdict != Verdict::pass) out << s.scene.name << ": " << to_string(s.verdict) << ": " << s.problem << "\n";
  // The counts, each verdict apart: a scene that ran without a check is not a pass.
  std::string counts;
  for (const Verdict v : {Verdict::pass, Verdict::unchecked, Verdict::fail, Verdict::bad_input, Verdict::error, Verdict::not_run}) {
    const auto n = std::count_if(scenes.begin(), scenes.end(), [&](const SceneOutcome& s) { return s.verdict == v; });
    if (n > 0) counts += (counts.empty() ? "" : ", ") + std::to_string(n) + " " + to_string(v);
  }
  out << scenes.size() << " scenes: " << counts << "\n";
}

}  // namespace aggkit

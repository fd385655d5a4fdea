#include "validation/validate/report_html.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "validation/io/text.hpp"
#include "validation/io/version.hpp"
#include "validation/validate/validation_table.hpp"

namespace aggkit {

namespace {

const char* style = R"(body{font-family:sans-serif;margin:1.5em;max-width:75em;color:#222}
table{border-collapse:collapse;margin:.5em 0 1em}th,td{border:1px solid #bbb;padding:.2em .5em;text-align:left;vertical-align:top}
th{background:#eee}td.num{text-align:right;font-variant-numeric:tabular-nums}
.pass{color:#060;font-weight:bold}.fail{color:#b00;font-weight:bold}.nocheck{color:#850;font-weight:bold}
.description{white-space:pre-wrap;background:#f6f6f6;padding:.5em;border-left:3px solid #999}
pre.log{background:#fee;padding:.5em;overflow-x:auto}
figure{display:inline-block;margin:.5em}figure img{max-width:100%;max-height:40em;border:1px solid #ccc}
figcaption{font-size:85%;color:#555}section{border-top:2px solid #ccc;margin-top:1.5em})";

std::string cell(const std::string& text, bool number = false) {
  return std::string(number ? "<td class=\"num\">" : "<td>") + html_escape(text) + "</td>";
}

const char* verdict_class(Verdict verdict) {
  return verdict == Verdict::pass ? "pass" : verdict == Verdict::unchecked ? "nocheck" : "fail";
}

std::string verdict_cell(Verdict verdict) {
  return std::string("<td class=\"") + verdict_class(verdict) + "\">" + html_escape(to_string(verdict)) + "</td>";
}

std::string optional_verdict_cell(const ComparisonLine& c) {
  if (!c.pass) return "<td>reported</td>";
  return *c.pass ? "<td class=\"pass\">pass</td>" : "<td class=\"fail\">FAIL</td>";
}

std::string anchor(const SceneOutcome& s) { return "scene-" + s.scene.folder; }

std::string number_text(double value) {
  if (std::isnan(value)) return "—";
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

// A CSV file as a table (at most `limit` rows); empty if it cannot be read.
std::string csv_table(const std::filesystem::path& file, std::size_t limit) {
  std::ifstream in(file);
  if (!in) return "";
  std::ostringstream html;
  html << "<table>";
  std::string line;
  for (std::size_t row = 0; row <= limit && std::getline(in, line); ++row) {
    html << "<tr>";
    std::istringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) html << (row == 0 ? "<th>" + html_escape(field) + "</th>" : cell(field));
    html << "</tr>";
  }
  html << "</table>";
  return html.str();
}

// The final values of a particle engine (DIR/<scene>/<label>/final.json: means, with `_stderr` standard errors).
std::string final_values_table(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) return "";
  const nlohmann::ordered_json values = nlohmann::ordered_json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!values.is_object()) return "";
  std::ostringstream html;
  html << "<table><tr><th>final value</th><th>mean</th><th>standard error</th></tr>";
  for (const auto& [name, value] : values.items()) {
    if (!value.is_number() || (name.size() > 7 && name.ends_with("_stderr"))) continue;
    const auto error = values.find(name + "_stderr");
    html << "<tr>" << cell(name) << cell(number_text(value.get<double>()), true)
         << cell(error != values.end() && error->is_number() ? number_text(error->get<double>()) : "", true) << "</tr>";
  }
  html << "</table>";
  return html.str();
}

void summary_table(std::ostream& html, const std::vector<SceneOutcome>& scenes) {
  html << "<table><tr><th>scene</th><th>tier</th><th>engines</th><th>worst comparison</th><th>error</th>"
          "<th>tolerance</th><th>used</th><th>wall s</th><th>result</th></tr>\n";
  for (const auto& s : scenes) {
    const ComparisonLine* worst = s.worst ? &s.comparisons[*s.worst] : nullptr;
    html << "<tr><td><a href=\"#" << html_escape(anchor(s)) << "\">" << html_escape(s.scene.name) << "</a></td>"
         << cell(to_string(s.scene.tier)) << cell(engines_text(s)) << cell(worst_text(s))
         << cell(worst ? error_text(*worst) : "", true) << cell(worst ? tolerance_text(*worst) : "", true)
         << cell(worst ? used_text(*worst) : "", true)
         << cell(seconds_text(s.wall_seconds) + (s.resumed ? " (earlier run)" : ""), true) << verdict_cell(s.verdict)
         << "</tr>\n";
  }
  html << "</table>\n";
}

void scene_section(std::ostream& html, const std::filesystem::path& out, const SceneOutcome& s) {
  html << "<section id=\"" << html_escape(anchor(s)) << "\"><h2>" << html_escape(s.scene.name) << " — <span class=\""
       << verdict_class(s.verdict) << "\">" << html_escape(to_string(s.verdict))
       << "</span></h2>\n";
  html << "<p>" << html_escape(s.scene.file.string()) << " · tier " << to_string(s.scene.tier) << " · aggkit "
       << to_string(s.scene.kind) << " · wall time " << html_escape(seconds_text(s.wall_seconds)) << " s"
       << (s.resumed ? " (finished in an earlier run)" : "") << "</p>\n";
  if (!s.scene.description.empty())
    html << "<div class=\"description\">" << html_escape(s.scene.description) << "</div>\n";
  if (!s.problem.empty())
    html << "<p class=\"" << verdict_class(s.verdict) << "\">" << html_escape(s.problem) << "</p>\n";
  if (!s.engines.empty()) {
    html << "<h3>Engines</h3><table><tr><th>label</th><th>engine</th><th>status</th><th>wall s</th><th>error</th></tr>\n";
    for (const auto& e : s.engines)
      html << "<tr>" << cell(e.label) << cell(e.name) << cell(e.status) << cell(seconds_text(e.wall_seconds), true)
           << cell(e.error) << "</tr>\n";
    html << "</table>\n";
  }
  for (const auto& e : s.engines) {
    const std::string finals = final_values_table(out / s.scene.folder / e.label / "final.json");
    if (!finals.empty()) html << "<h3>Final values of " << html_escape(e.label) << "</h3>" << finals << "\n";
  }
  if (!s.comparisons.empty()) {
    html << "<h3>Comparisons</h3><table><tr><th>engine</th><th>reference</th><th>observable</th><th>kind</th>"
            "<th>max relative error</th><th>at t</th><th>tolerance</th><th>used</th><th>result</th><th>note</th></tr>\n";
    for (const auto& c : s.comparisons)
      html << "<tr>" << cell(c.engine) << cell(c.reference) << cell(c.observable) << cell(c.kind)
           << cell(error_text(c), true) << cell(number_text(c.time), true) << cell(tolerance_text(c), true)
           << cell(used_text(c), true) << optional_verdict_cell(c) << cell(c.note) << "</tr>\n";
    html << "</table>\n";
  } else if (s.scene.kind == SceneKind::run && (s.verdict == Verdict::unchecked || s.verdict == Verdict::fail)) {
    html << "<p>No comparisons: the scene ran, and nothing in it was checked.</p>\n";
  }
  if (s.scene.kind == SceneKind::scan) {
    html << "<p>" << s.scan_points << " (a, λ) points classified (" << html_escape(s.scene.folder)
         << "/scan.csv).</p>\n";
    const std::string crit = csv_table(out / s.scene.folder / "lambda_crit.csv", 40);
    if (!crit.empty()) html << "<h3>λ_crit(a)</h3>" << crit << "\n";
  }
  if (!s.log_tail.empty())
    html << "<h3>End of the log (" << html_escape("logs/" + s.scene.folder + ".log") << ")</h3><pre class=\"log\">"
         << html_escape(s.log_tail) << "</pre>\n";
  if (!s.images.empty()) {
    html << "<h3>Plots</h3>\n";
    for (const auto& image : s.images)
      html << "<figure><a href=\"" << html_escape(url_path(image)) << "\"><img src=\"" << html_escape(url_path(image))
           << "\" alt=\"" << html_escape(image) << "\"></a><figcaption>" << html_escape(image)
           << "</figcaption></figure>\n";
  }
  html << "</section>\n";
}

}  // namespace

std::string html_escape(const std::string& text) {
  std::string escaped;
  escaped.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': escaped += "&amp;"; break;
      case '<': escaped += "&lt;"; break;
      case '>': escaped += "&gt;"; break;
      case '"': escaped += "&quot;"; break;
      case '\'': escaped += "&#39;"; break;
      default: escaped += c;
    }
  }
  return escaped;
}

std::string url_path(const std::string& relative) {
  std::string url;
  for (const unsigned char c : relative) {
    const bool plain = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' ||
                       c == '.' || c == '_' || c == '~' || c == '/';
    if (plain) {
      url += char(c);
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", c);
      url += hex;
    }
  }
  return url;
}

std::string report_html(const std::filesystem::path& out, const std::vector<SceneOutcome>& scenes,
                        const ValidationTotals& totals) {
  std::size_t passed = 0, unchecked = 0;
  for (const auto& s : scenes) {
    passed += s.verdict == Verdict::pass ? 1 : 0;
    unchecked += s.verdict == Verdict::unchecked ? 1 : 0;
  }
  const std::string headline = std::to_string(passed) + " of " + std::to_string(scenes.size()) + " scenes pass" +
                               (unchecked ? ", " + std::to_string(unchecked) + " ran (no check)" : "");
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>aggkit validate: " << headline
       << "</title>\n<style>" << style << "</style></head><body>\n";
  html << "<h1>aggkit validate — " << (totals.exit_code == 0 ? "<span class=\"pass\">" : "<span class=\"fail\">")
       << headline << "</span></h1>\n";
  html << "<p>aggkit " << html_escape(version()) << " · tier " << to_string(totals.tier) << " · " << totals.jobs
       << (totals.jobs == 1 ? " job" : " jobs") << " · wall time " << html_escape(seconds_text(totals.wall_seconds))
       << " s (this run) · exit status " << totals.exit_code
       << ". Error: the largest relative error over the output times (with σ: in combined standard errors); "
          "tolerance: relative (+ k σ); used: the largest share of the allowed error, ≤ 100 % passes.</p>\n";
  summary_table(html, scenes);
  if (!totals.notes.empty()) {
    html << "<p>Left out:</p><ul>";
    for (const auto& note : totals.notes) html << "<li>" << html_escape(note) << "</li>";
    html << "</ul>\n";
  }
  for (const auto& s : scenes) scene_section(html, out, s);
  html << "</body></html>\n";
  return html.str();
}

}  // namespace aggkit

#include "validation/harness/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "validation/io/text.hpp"

namespace aggkit {

namespace {

std::string format(const char* pattern, auto... values) {
  char line[512];
  std::snprintf(line, sizeof line, pattern, values...);
  return line;
}

std::string scientific(double value) { return std::isnan(value) ? "nan" : format("%.3e", value); }

}  // namespace

void print_report(std::ostream& out, const Scene& scene, const RunResult& result, const OutputFolder& folder) {
  out << "scene " << scene.name;
  if (!scene.path.empty()) out << " (" << scene.path.string() << ")";
  if (scene.has_model)
    out << ": " << scene.model.kernel.describe() << ", lambda = " << scene.model.lambda.describe()
        << ", N = " << scene.model.size;
  if (scene.particles) out << (scene.has_model ? "; " : ": ") << scene.particles->describe();
  out << ", t in (0, " << shortest_text(scene.time.end) << "], "
      << scene.time.outputs.size() << " outputs\n\n";

  out << format("  %-16s %-8s %10s %16s  %s\n", "engine", "kind", "wall [s]", "final mass_leak", "status");
  for (const auto& r : result.records)
    out << format("  %-16s %-8s %10.3f %16s  %s\n", r.label.c_str(), r.name.c_str(), r.wall_seconds,
                  scientific(r.final_mass_leak).c_str(), r.completed() ? "completed" : "FAILED");
  for (const auto& r : result.records)
    if (r.failure) out << "  " << r.label << " failed: " << *r.failure << "\n";

  if (!result.comparisons.empty()) {
    std::vector<std::string> references;  // the reference engine and/or "stated value", in order
    for (const auto& c : result.comparisons)
      if (std::find(references.begin(), references.end(), c.reference) == references.end()) references.push_back(c.reference);
    out << "\ncomparison with " << join(references) << " (largest relative error over the output times)\n";
    out << format("  %-16s %-12s %14s %12s %12s  %s\n", "engine", "observable", "max rel. error", "at t", "tolerance",
                  "result");
    for (const auto& c : result.comparisons) {
      std::string tolerance = c.tolerance ? scientific(*c.tolerance) : "-";
      if (c.stderr_multiple) tolerance += " + " + shortest_text(*c.stderr_multiple) + " se";
      std::string outcome = !c.tolerance ? "(reported)" : c.pass ? "PASS" : "FAIL";
      if (!std::isnan(c.max_standard_errors)) outcome += format(" (max %.2f se)", c.max_standard_errors);
      const std::string name = c.final_state ? "final " + c.observable : c.observable;
      out << format("  %-16s %-12s %14s %12s %12s  %s\n", c.engine.c_str(), name.c_str(),
                    scientific(c.max_relative_error).c_str(), (c.final_state ? std::string("end") : shortest_text(c.time)).c_str(), tolerance.c_str(),
                    outcome.c_str());
      if (!c.note.empty()) out << "      " << c.note << "\n";
    }
  }
  if (result.plot.status == PlotOutcome::Status::failed) out << "\nplot failed: " << result.plot.message << "\n";
  out << "\n" << (result.pass ? "PASS" : "FAIL") << "  (outputs in " << folder.root().string() << ")\n";
}

}  // namespace aggkit

#pragma once
// The pass/fail table of a validation (printed at the end) and the text forms of its cells, shared with
// report.html: one row per scene — scene, tier, engines, the worst comparison, its error against its
// tolerance and the share of the tolerance used, wall time, verdict.
#include <ostream>
#include <string>
#include <vector>

#include "validation/validate/scene_outcome.hpp"

namespace aggkit {

std::string seconds_text(double seconds);            // "1.2", "35", "—" for NaN
std::string error_text(const ComparisonLine& c);     // "3.1e-10", "2.1e-03 (1.3 σ)", "NaN"
std::string tolerance_text(const ComparisonLine& c);  // "1e-06", "0.005 + 5 σ", "none"
std::string used_text(const ComparisonLine& c);      // "31 %", "—"
std::string worst_text(const SceneOutcome& outcome);  // "cvode M3 vs exact", "no comparisons", "210 points"
std::string engines_text(const SceneOutcome& outcome);

void print_validation_table(std::ostream& out, const std::vector<SceneOutcome>& scenes);

}  // namespace aggkit

#pragma once
// The short human summary of a run on stdout: engines (time, status), the comparison table with
// PASS/FAIL per observable, and the verdict.
#include <ostream>

#include "validation/harness/output_folder.hpp"
#include "validation/harness/run_result.hpp"
#include "validation/scene/scene.hpp"

namespace aggkit {

void print_report(std::ostream& out, const Scene& scene, const RunResult& result, const OutputFolder& folder);

}  // namespace aggkit

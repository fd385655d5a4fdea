#pragma once
// DIR/summary.json: the machine-readable record of a run (written last; see output_folder.hpp):
//   { "aggkit_version", "scene": { name, path, model, time },
//     "engines": { <label>: { name, description, status, error?, wall_seconds, final_mass_leak,
//                             outputs, statistics: { ... } } },
//     "comparisons": [ { engine, reference, observable, kind, max_relative_error, time, tolerance, pass,
//                        tolerance_stderr?, tolerance_used?, max_error_in_stderr?, note? } ],
//     (tolerance_used: the largest share of the allowed error, max |x - x_ref| / allowed; <= 1 passes)
//     "plot": { status, file?, message? }, "pass", "exit_code" }
// Numbers that are not finite are written as null.
#include <string>

#include "validation/harness/output_folder.hpp"
#include "validation/harness/run_result.hpp"
#include "validation/scene/scene.hpp"

namespace aggkit {

std::string summary_json(const Scene& scene, const RunResult& result, const OutputFolder& folder);

}  // namespace aggkit

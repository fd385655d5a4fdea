#pragma once
// Everything a finished run produced: what summary.json and the stdout report are written from.
#include <vector>

#include "validation/harness/comparison.hpp"
#include "validation/harness/engine_record.hpp"
#include "validation/io/exit_code.hpp"
#include "validation/harness/plot.hpp"

namespace aggkit {

struct RunResult {
  std::vector<EngineRecord> records;  // in scene order
  std::vector<ComparisonResult> comparisons;
  PlotOutcome plot;
  bool pass = true;  // every engine completed and every comparison passed
  int exit_code = exit_pass;
};

}  // namespace aggkit

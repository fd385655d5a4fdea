#pragma once
// One finished run of a sweep (a point and a realization): its file DIR/points/point<i>_r<r>.json, which marks
// it finished, and the CSV tables built from all of them (sweep.hpp).
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "validation/sweep/sweep_plan.hpp"

namespace aggkit {

struct SweepRecord {
  std::size_t point = 0, realization = 0;
  std::vector<nlohmann::json> values;                    // the swept values, one per key
  std::vector<std::pair<std::string, double>> columns;   // final values, in order (NaN: undefined)
  double seconds = 0;
  int rank = 0;
};

std::string record_file_text(const SweepRecord& record);
// The record in `text` if it is a complete record of run (point, realization) with these values; else nullopt.
std::optional<SweepRecord> parse_record_file(const std::string& text, std::size_t point, std::size_t realization,
                                             const std::vector<nlohmann::json>& values);

// sweep.csv, sweep_mean.csv and timing.csv from the records (ordered by point, then realization).
std::string sweep_csv(const SweepPlan& plan, const std::vector<SweepRecord>& records);
std::string sweep_mean_csv(const SweepPlan& plan, const std::vector<SweepRecord>& records);
std::string sweep_timing_csv(const std::vector<SweepRecord>& records);
// The means over every run whose swept values of `grouping` (indices into plan.axes) are equal, pooled over
// the other keys and the realizations: a row per distinct value (in order of first appearance), the grouped
// keys, runs, then <name>, <name>_stderr, <name>_n as in sweep_mean.csv.
std::string sweep_pooled_csv(const SweepPlan& plan, const std::vector<SweepRecord>& records, const std::vector<std::size_t>& grouping);
// The records with plan.not_aggregated applied: in each run whose aggregation_time is NaN, those columns
// take their given values.
std::vector<SweepRecord> fill_not_aggregated(const SweepPlan& plan, std::vector<SweepRecord> records);

// A CSV cell: quoted (with doubled quotes) if it holds a comma, a quote or a line break.
std::string csv_cell(const std::string& text);

}  // namespace aggkit

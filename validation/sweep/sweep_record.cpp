#include "validation/sweep/sweep_record.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>

#include "validation/io/text.hpp"
#include "validation/runs/json_record.hpp"

namespace aggkit {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// Every column of the records, in order of first appearance.
std::vector<std::string> column_names(const std::vector<SweepRecord>& records) {
  std::vector<std::string> names;
  std::map<std::string, bool> seen;
  for (const auto& r : records)
    for (const auto& [name, value] : r.columns)
      if (!seen[name]) seen[name] = true, names.push_back(name);
  return names;
}

double column(const SweepRecord& record, const std::string& name) {
  for (const auto& [n, v] : record.columns)
    if (n == name) return v;
  return nan;
}

std::string values_cells(const SweepPlan& plan, const std::vector<nlohmann::json>& values) {
  std::string text;
  for (std::size_t a = 0; a < plan.axes.size(); ++a) text += csv_cell(sweep_value_text(values[a])) + ",";
  return text;
}

std::string keys_header(const SweepPlan& plan) {
  std::string text;
  for (const auto& axis : plan.axes) text += csv_cell(axis.key) + ",";
  return text;
}

// Mean, standard error (sample standard deviation / √n; 0 for n = 1) and n over the finite values of column
// `name` in records[k] for k in `runs`.
void append_mean_cells(std::string& text, const std::vector<SweepRecord>& records, const std::vector<std::size_t>& runs,
                       const std::string& name);

// Appends ",cell" in two steps (`text += "," + cell` trips GCC 12's -Wrestrict false positive).
void append_cell(std::string& text, const std::string& cell) {
  text += ',';
  text += cell;
}

}  // namespace

std::string csv_cell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string record_file_text(const SweepRecord& r) {
  nlohmann::json columns = nlohmann::json::array();
  for (const auto& [name, value] : r.columns)
    columns.push_back({name, std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr)});
  const nlohmann::json j{{"point", r.point},     {"realization", r.realization}, {"values", r.values},
                         {"columns", columns},   {"seconds", r.seconds},         {"rank", r.rank}};
  return j.dump(1) + "\n";
}

std::optional<SweepRecord> parse_record_file(const std::string& text, std::size_t point, std::size_t realization,
                                             const std::vector<nlohmann::json>& values) {
  const std::optional<nlohmann::json> record = json_record(text);
  if (!record) return std::nullopt;
  try {
    const nlohmann::json& j = *record;
    // The counts are read only from JSON integers: nlohmann's get<integer>() of a float casts it, which is
    // undefined behaviour out of the integer's range (1e300) and truncates inside it (0.5 would read as point 0).
    if (!j.at("point").is_number_unsigned() || !j.at("realization").is_number_unsigned() ||
        !j.at("rank").is_number_integer())
      return std::nullopt;
    SweepRecord r;
    r.point = j.at("point").get<std::size_t>();
    r.realization = j.at("realization").get<std::size_t>();
    r.values = j.at("values").get<std::vector<nlohmann::json>>();
    if (r.point != point || r.realization != realization || r.values != values) return std::nullopt;
    for (const auto& c : j.at("columns")) {
      const nlohmann::json& v = c.at(1);
      r.columns.emplace_back(c.at(0).get<std::string>(), v.is_null() ? nan : v.get<double>());
    }
    r.seconds = j.at("seconds").get<double>();
    const std::int64_t rank = j.at("rank").get<std::int64_t>();
    if (rank < 0 || rank > std::numeric_limits<int>::max()) return std::nullopt;
    r.rank = int(rank);
    return r;
  } catch (const std::exception&) {
    return std::nullopt;  // damaged or of another format: the run is done again
  }
}

std::string sweep_csv(const SweepPlan& plan, const std::vector<SweepRecord>& records) {
  const std::vector<std::string> names = column_names(records);
  std::string text = keys_header(plan) + "realization";
  for (const auto& n : names) append_cell(text, csv_cell(n));
  text += "\n";
  for (const auto& r : records) {
    text += values_cells(plan, r.values) + std::to_string(r.realization);
    for (const auto& n : names) append_cell(text, shortest_text(column(r, n)));
    text += "\n";
  }
  return text;
}

std::string sweep_mean_csv(const SweepPlan& plan, const std::vector<SweepRecord>& records) {
  const std::vector<std::string> names = column_names(records);
  std::string text = keys_header(plan) + "runs";
  for (const auto& n : names) {
    append_cell(text, csv_cell(n));
    append_cell(text, csv_cell(n + "_stderr"));
    append_cell(text, csv_cell(n + "_n"));
  }
  text += "\n";
  for (std::size_t begin = 0; begin < records.size();) {
    std::size_t end = begin;
    while (end < records.size() && records[end].point == records[begin].point) ++end;
    text += values_cells(plan, records[begin].values) + std::to_string(end - begin);
    std::vector<std::size_t> runs;
    for (std::size_t k = begin; k < end; ++k) runs.push_back(k);
    for (const auto& n : names) append_mean_cells(text, records, runs, n);
    text += "\n";
    begin = end;
  }
  return text;
}

namespace {

void append_mean_cells(std::string& text, const std::vector<SweepRecord>& records, const std::vector<std::size_t>& runs,
                       const std::string& name) {
  // Mean and standard error over the runs where the value is finite (T_agg only where it aggregated).
  double sum = 0, sum_squares = 0;
  std::size_t count = 0;
  for (std::size_t k : runs)
    if (const double v = column(records[k], name); std::isfinite(v)) sum += v, ++count;
  const double mean = count ? sum / double(count) : nan;
  for (std::size_t k : runs)
    if (const double v = column(records[k], name); std::isfinite(v)) sum_squares += (v - mean) * (v - mean);
  const double stderr_ = count > 1 ? std::sqrt(sum_squares / double(count - 1) / double(count)) : count == 1 ? 0.0 : nan;
  append_cell(text, shortest_text(mean));
  append_cell(text, shortest_text(stderr_));
  append_cell(text, std::to_string(count));
}

}  // namespace

std::string sweep_pooled_csv(const SweepPlan& plan, const std::vector<SweepRecord>& records, const std::vector<std::size_t>& grouping) {
  const std::vector<std::string> names = column_names(records);
  std::string text;
  for (std::size_t a : grouping) text += csv_cell(plan.axes[a].key) + ",";
  text += "runs";
  for (const auto& n : names) {
    append_cell(text, csv_cell(n));
    append_cell(text, csv_cell(n + "_stderr"));
    append_cell(text, csv_cell(n + "_n"));
  }
  text += "\n";
  // The groups in order of first appearance, each with its runs.
  std::vector<std::vector<nlohmann::json>> keys;
  std::vector<std::vector<std::size_t>> members;
  for (std::size_t k = 0; k < records.size(); ++k) {
    std::vector<nlohmann::json> key;
    for (std::size_t a : grouping) key.push_back(records[k].values[a]);
    const auto found = std::find(keys.begin(), keys.end(), key);
    if (found == keys.end()) keys.push_back(key), members.push_back({k});
    else members[std::size_t(found - keys.begin())].push_back(k);
  }
  for (std::size_t g = 0; g < keys.size(); ++g) {
    for (const auto& value : keys[g]) text += csv_cell(sweep_value_text(value)) + ",";
    text += std::to_string(members[g].size());
    for (const auto& n : names) append_mean_cells(text, records, members[g], n);
    text += "\n";
  }
  return text;
}

std::vector<SweepRecord> fill_not_aggregated(const SweepPlan& plan, std::vector<SweepRecord> records) {
  if (plan.not_aggregated.empty()) return records;
  for (SweepRecord& r : records) {
    if (!std::isnan(column(r, "aggregation_time"))) continue;
    for (const auto& [name, value] : plan.not_aggregated)
      for (auto& [n, v] : r.columns)
        if (n == name) v = value;
  }
  return records;
}

std::string sweep_timing_csv(const std::vector<SweepRecord>& records) {
  std::string text = "point,realization,seconds,rank\n";
  for (const auto& r : records)
    text += std::to_string(r.point) + "," + std::to_string(r.realization) + "," + shortest_text(r.seconds) + "," +
            std::to_string(r.rank) + "\n";
  return text;
}

}  // namespace aggkit

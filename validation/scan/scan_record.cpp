#include "validation/scan/scan_record.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "validation/io/text.hpp"
#include "validation/runs/run_store.hpp"

namespace aggkit {

void record_run(const OscillationClassification& c, double end, ScanRecord& r) {
  r.regime = to_string(c.regime);
  r.period = c.period;
  r.amplitude = c.amplitude;
  r.mean = c.mean;
  r.decay_rate = c.decay_rate;
  r.decay_rate_error = c.decay_rate_error;
  r.cycles = c.cycles;
  r.converged = c.converged;
  r.run_end = end;
  if (!c.note.empty()) r.note = c.note + (r.note.empty() ? "" : "; " + r.note);
}

namespace {

const char* const columns =
    "a,lambda,regime,period,amplitude,mean,decay_rate,decay_rate_error,cycles,converged,"
    "regime_stability,rightmost_real,rightmost_imag,agree,N,index,note,mean_steady,regime_refined,"
    "steady_how,spectrum_converged,verdict,cycle_period,cycle_m0_min,cycle_m0_max,floquet_max,cycle_stable,run_end";
const char* const point_columns = ",seconds,rank";

std::string clean(std::string text) {
  std::replace_if(text.begin(), text.end(), [](char c) { return c == ',' || c == '\n' || c == '\r' || c == '"'; }, ';');
  return text;
}

}  // namespace

std::string outcome_summary(const ScanRecord& r) {
  const auto number = [](double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", x);
    return std::string(text);
  };
  std::string words = r.regime.empty() ? "no verdict" : r.regime;
  if (r.regime == "damped") {
    if (std::isfinite(r.decay_rate)) words += ", decay rate " + number(r.decay_rate);
    if (std::isfinite(r.period)) words += " (period " + number(r.period) + ")";
  } else if (r.regime == "sustained" || r.regime == "irregular") {
    if (std::isfinite(r.period)) words += ", period " + number(r.period);
    if (std::isfinite(r.amplitude)) words += ", amplitude " + number(r.amplitude);
  }
  return words;
}

std::string scan_csv_header() { return columns; }

std::string scan_csv_row(const ScanRecord& r) {
  const auto number = [](double v) { return shortest_text(v); };
  return number(r.a) + "," + number(r.lambda) + "," + r.regime + "," + number(r.period) + "," + number(r.amplitude) +
         "," + number(r.mean) + "," + number(r.decay_rate) + "," + number(r.decay_rate_error) + "," +
         std::to_string(r.cycles) + "," + (r.converged ? "yes" : "no") + "," + r.regime_stability + "," +
         number(r.rightmost_real) + "," + number(r.rightmost_imag) + "," + r.agree + "," + std::to_string(r.size) +
         "," + std::to_string(r.index) + "," + clean(r.note) + "," + number(r.mean_steady) + "," + r.regime_refined +
         "," + clean(r.steady_how) + "," + r.spectrum_converged + "," + r.verdict + "," + number(r.cycle_period) + "," +
         number(r.cycle_m0_min) + "," + number(r.cycle_m0_max) + "," + number(r.floquet_max) + "," + r.cycle_stable + "," + number(r.run_end);
}

std::string point_file_text(const ScanRecord& r) {
  return scan_csv_header() + point_columns + "\n" + scan_csv_row(r) + "," + shortest_text(r.seconds) + "," +
         std::to_string(r.rank) + "\n";
}

std::optional<ScanRecord> parse_point_file(const std::string& text) {
  const auto fields = one_row_record(text, scan_csv_header() + point_columns);
  if (!fields || fields->size() != 30) return std::nullopt;
  const std::vector<std::string>& f = *fields;
  try {
    ScanRecord r;
    r.a = std::stod(f[0]);
    r.lambda = std::stod(f[1]);
    r.regime = f[2];
    r.period = std::stod(f[3]);
    r.amplitude = std::stod(f[4]);
    r.mean = std::stod(f[5]);
    r.decay_rate = std::stod(f[6]);
    r.decay_rate_error = std::stod(f[7]);
    r.cycles = std::stoul(f[8]);
    r.converged = f[9] == "yes";
    r.regime_stability = f[10];
    r.rightmost_real = std::stod(f[11]);
    r.rightmost_imag = std::stod(f[12]);
    r.agree = f[13];
    r.size = std::stoul(f[14]);
    r.index = std::stoul(f[15]);
    r.note = f[16];
    r.mean_steady = std::stod(f[17]);
    r.regime_refined = f[18];
    r.steady_how = f[19];
    r.spectrum_converged = f[20];
    r.verdict = f[21];
    r.cycle_period = std::stod(f[22]);
    r.cycle_m0_min = std::stod(f[23]);
    r.cycle_m0_max = std::stod(f[24]);
    r.floquet_max = std::stod(f[25]);
    r.cycle_stable = f[26];
    r.run_end = std::stod(f[27]);
    r.seconds = std::stod(f[28]);
    r.rank = std::stoi(f[29]);
    if (r.regime.empty()) return std::nullopt;
    return r;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

}  // namespace aggkit

#include "validation/scan/scan_column_files.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "analysis/text.hpp"
#include "validation/runs/run_store.hpp"

namespace aggkit {

// The atol of the steps cached before atol and atol_mass were recorded: the integrator's default, rtol/100 at
// the columns' rtol 1e-6.
static constexpr double atol_before_tolerances = 1e-6 / 100.0;

// The column files' header. Steps cached by earlier versions have its first 19 fields (before the settling was
// recorded: read back as settled where converged), 22 (before atol and atol_mass: their runs took rtol/100 and
// no bound), 24 (before the step budget) or 25 (before the grid's end was watched: read back as unknown, NaN).
const char* const header =
    "a,lambda,periods,grid,regime,period,amplitude,mean,decay_rate,decay_rate_error,cycles,converged,m0_min,m0_max,"
    "run_end,from_lambda,atol_floor,mass_change,note,settling,spread,contraction,atol,atol_mass,step_budget,"
    "leaked_mass,top_octave_mass";
constexpr std::array<std::size_t, 5> header_versions = {27, 25, 24, 22, 19};

// The header's first `fields` names.
static std::string header_prefix(std::size_t fields) {
  const std::string all = header;
  std::size_t end = 0;
  for (std::size_t i = 0; i < fields && end != std::string::npos; ++i) end = all.find(',', end + 1);
  return all.substr(0, end);
}

static std::string csv_safe(std::string text) {
  for (char& c : text)
    if (c == ',' || c == '\n') c = ';';
  return text;
}

std::string file_text(const ColumnCycle& c, std::size_t periods, const std::string& grid) {
  const auto n = [](double x) { return shortest_text(x); };
  const OscillationClassification& k = c.run;
  return std::string(header) + "\n" + n(c.a) + "," + n(c.lambda) + "," + std::to_string(periods) + "," + csv_safe(grid) +
         "," + (c.classified ? to_string(k.regime) : "") + "," + n(k.period) + "," + n(k.amplitude) + "," + n(k.mean) + "," +
         n(k.decay_rate) + "," + n(k.decay_rate_error) + "," + std::to_string(k.cycles) + "," + (k.converged ? "yes" : "no") + "," +
         n(c.m0_min) + "," + n(c.m0_max) + "," + n(c.run_end) + "," + n(c.from_lambda) + "," + n(c.atol_floor) + "," + n(c.mass_change) + "," + csv_safe(c.note) +
         "," + to_string(c.settling) + "," + n(c.spread) + "," + n(c.contraction) + "," + n(c.atol) + "," + n(c.atol_mass) + "," + std::to_string(c.step_budget) + "," + n(c.leaked_mass) + "," +
         n(c.top_octave_mass) + "\n";
}

static std::optional<CycleSettling> settling_from(const std::string& text) {
  for (CycleSettling s : {CycleSettling::too_few_crossings, CycleSettling::settling, CycleSettling::settled, CycleSettling::unsettled})
    if (text == to_string(s)) return s;
  return std::nullopt;
}

// The cached step, if its file is whole and was computed with these settings: a step that stopped the column
// only under the same step budget (the budget is not known for a step cached before it was recorded).
std::optional<ColumnCycle> parse_file(const std::string& text, double a, double lambda, std::size_t periods,
                                      const std::string& grid, std::size_t step_budget) {
  std::optional<std::vector<std::string>> f;
  std::size_t fields = 0;
  for (std::size_t version : header_versions)
    if ((f = one_row_record(text, header_prefix(version)))) {
      fields = version;
      break;
    }
  if (!f || f->size() != fields) return std::nullopt;
  std::vector<double> x;
  for (std::size_t i : {0, 1, 5, 6, 7, 8, 9, 12, 13, 14, 15, 16, 17}) {
    const auto v = record_number((*f)[i], true);
    if (!v) return std::nullopt;
    x.push_back(*v);
  }
  const auto cycles = record_number((*f)[10]);
  if (x[0] != a || x[1] != lambda || (*f)[2] != std::to_string(periods) || (*f)[3] != csv_safe(grid) || !cycles ||
      ((*f)[11] != "yes" && (*f)[11] != "no"))
    return std::nullopt;
  ColumnCycle c;
  c.a = a;
  c.lambda = lambda;
  for (Regime regime : {Regime::steady, Regime::damped, Regime::sustained, Regime::irregular})
    if ((*f)[4] == to_string(regime)) {
      c.classified = true;
      c.run.regime = regime;
    }
  if (!c.classified && !(*f)[4].empty()) return std::nullopt;
  c.run.period = x[2];
  c.run.amplitude = x[3];
  c.run.mean = x[4];
  c.run.decay_rate = x[5];
  c.run.decay_rate_error = x[6];
  c.run.cycles = std::size_t(*cycles);
  c.run.converged = (*f)[11] == "yes";
  c.m0_min = x[7];
  c.m0_max = x[8];
  c.run_end = x[9];
  c.from_lambda = x[10];
  c.atol_floor = x[11];
  c.mass_change = x[12];
  c.note = (*f)[18];
  c.atol = atol_before_tolerances;
  c.atol_mass = 0.0;
  if (fields >= 24) {
    const auto atol = record_number((*f)[22], true), atol_mass = record_number((*f)[23], true);
    if (!atol || !atol_mass) return std::nullopt;
    c.atol = *atol;
    c.atol_mass = *atol_mass;
  }
  if (fields >= 25) {
    const auto budget = record_number((*f)[24]);
    if (!budget) return std::nullopt;
    c.step_budget = std::size_t(*budget);
  }
  if (fields == 27) {
    const auto leaked = record_number((*f)[25], true), top = record_number((*f)[26], true);
    if (!leaked || !top) return std::nullopt;
    c.leaked_mass = *leaked;
    c.top_octave_mass = *top;
  }
  if (fields == 19) {
    c.settling = c.run.converged ? CycleSettling::settled : CycleSettling::settling;
    return c;
  }
  const auto settling = settling_from((*f)[19]);
  const auto spread = record_number((*f)[20], true), contraction = record_number((*f)[21], true);
  if (!settling || !spread || !contraction) return std::nullopt;
  c.settling = *settling;
  c.spread = *spread;
  c.contraction = *contraction;
  // A stop is the budget's verdict only under that budget; a cycle that outgrew the grid stops the column under any.
  if (!c.sustained() && !c.outgrew_grid() && c.step_budget != 0 && c.step_budget != step_budget) return std::nullopt;
  return c;
}

std::string state_text(const std::vector<double>& state) {
  std::string text;
  for (double v : state) text += shortest_text(v) + "\n";
  return text;
}

std::optional<std::vector<double>> parse_state(const std::string& text, std::size_t unknowns) {
  std::vector<double> state;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const auto v = record_number(line);
    if (!v) return std::nullopt;
    state.push_back(*v);
  }
  if (state.size() != unknowns) return std::nullopt;
  return state;
}

// The Floquet multiplier's file beside a step's record.
const char* const floquet_header = "a,lambda,multiplier,multiplier_error,bounded,floor,deviations,seconds,note";

std::string floquet_text(const ColumnCycle& c) {
  const auto n = [](double x) { return shortest_text(x); };
  const ReturnMapMultiplier& m = c.floquet;
  std::string deviations;
  for (double d : m.deviations) {
    if (!deviations.empty()) deviations += ';';
    deviations += short_number(d);
  }
  return std::string(floquet_header) + "\n" + n(c.a) + "," + n(c.lambda) + "," + n(m.multiplier) + "," + n(m.multiplier_error) + "," +
         (m.bounded ? "yes" : "no") + "," + n(m.floor) + "," + deviations + "," + n(m.seconds) + "," + csv_safe(m.note) + "\n";
}

// Reads the multiplier into c where the file is whole and belongs to c's step.
void parse_floquet(const std::string& text, ColumnCycle& c) {
  const auto f = one_row_record(text, floquet_header);
  if (!f || f->size() != 9) return;
  const auto a = record_number((*f)[0]), lambda = record_number((*f)[1]), multiplier = record_number((*f)[2], true),
             error = record_number((*f)[3], true), floor = record_number((*f)[5], true), seconds = record_number((*f)[7], true);
  if (!a || !lambda || *a != c.a || *lambda != c.lambda || !multiplier || !error || !floor || !seconds ||
      ((*f)[4] != "yes" && (*f)[4] != "no"))
    return;
  ReturnMapMultiplier m;
  m.multiplier = *multiplier;
  m.multiplier_error = *error;
  m.bounded = (*f)[4] == "yes";
  m.floor = *floor;
  std::istringstream deviations((*f)[6]);
  for (std::string d; std::getline(deviations, d, ';');) {
    const auto v = record_number(d);
    if (!v) return;
    m.deviations.push_back(*v);
  }
  m.seconds = *seconds;
  m.note = (*f)[8];
  // The estimate is derived again from the recorded deviations (measure_floquet's resolved_factor): the cache keeps
  // the measurement, so a file written before a change of the estimate's rules reads as the rules now say.
  if (!m.deviations.empty()) estimate_multiplier(m.deviations, ReturnMapOptions{}.resolved_factor * m.floor, m);
  c.floquet = std::move(m);
  c.floquet_done = true;
}

// One column: the plan's λ below the first cycle's, walked downwards from it.

}  // namespace aggkit

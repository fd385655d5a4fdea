#include "validation/scan/scan_output.hpp"

#include <cmath>

#include "validation/io/atomic_file.hpp"
#include "validation/io/child_process.hpp"
#include "validation/io/python_plotter.hpp"
#include "validation/io/text.hpp"

namespace aggkit {

namespace {

std::string number(double v) { return shortest_text(v); }

std::string relative_change(double value, double reference) {
  return number(std::abs(value - reference) / std::abs(reference));
}

std::filesystem::path plot_scan_script() {
  return plot_script("AGGKIT_PLOT_SCAN_SCRIPT", AGGKIT_PLOT_SCAN_SCRIPT_BUILD, AGGKIT_PLOT_SCAN_SCRIPT_INSTALL);
}

}  // namespace

void write_scan_csv(const std::filesystem::path& file, const std::vector<ScanRecord>& records) {
  std::string text = scan_csv_header() + "\n";
  for (const auto& r : records) text += scan_csv_row(r) + "\n";
  write_file_atomically(file, text);
}

void write_timing_csv(const std::filesystem::path& file, const std::vector<ScanRecord>& records) {
  std::string text = "a,lambda,N,seconds,rank\n";
  for (const auto& r : records)
    text += number(r.a) + "," + number(r.lambda) + "," + std::to_string(r.size) + "," + number(r.seconds) + "," +
            std::to_string(r.rank) + "\n";
  write_file_atomically(file, text);
}

void write_lambda_crit_csv(const std::filesystem::path& file, const std::vector<LambdaCritRow>& rows) {
  std::string text =
      "a,lambda_crit,lambda_crit_error,method,lambda_sustained,lambda_relaxing,period,N,lambda_crit_2N,change_2N,note,"
      "resolved,ratio,lambda_crit_2K,change_2K,lambda_crit_half_ratio,change_half_ratio,converged,lambda_crit_scan_grid,"
      "lyapunov,criticality,m0_half_range_predicted\n";
  for (const auto& r : rows) {
    std::string note = r.note;
    for (char& c : note)
      if (c == ',' || c == '\n' || c == '"') c = ';';
    text += number(r.a) + "," + number(r.lambda_crit) + "," + number(r.error) + "," + r.method + "," +
            number(r.lambda_sustained) + "," + number(r.lambda_relaxing) + "," + number(r.period) + "," +
            std::to_string(r.size) + "," + number(r.lambda_crit_2N) + "," + number(r.change_2N) + "," + note + "," +
            std::to_string(r.resolved) + "," + number(r.ratio) + "," + number(r.lambda_crit_2K) + "," +
            number(r.change_2K) + "," + number(r.lambda_crit_half_ratio) + "," + number(r.change_half_ratio) + "," +
            r.converged + "," + number(r.lambda_crit_model_grid) + "," + number(r.lyapunov) + "," + r.criticality + "," + number(r.m0_half_range) + "\n";
  }
  write_file_atomically(file, text);
}

void write_truncation_check_csv(const std::filesystem::path& file, const std::vector<TruncationCheckRow>& rows) {
  std::string text =
      "a,lambda,N,regime,period,amplitude,regime_2N,period_2N,amplitude_2N,period_change,amplitude_change\n";
  for (const auto& [n, n2] : rows)
    text += number(n.a) + "," + number(n.lambda) + "," + std::to_string(n.size) + "," + n.regime + "," +
            number(n.period) + "," + number(n.amplitude) + "," + n2.regime + "," + number(n2.period) + "," +
            number(n2.amplitude) + "," + relative_change(n2.period, n.period) + "," +
            relative_change(n2.amplitude, n.amplitude) + "\n";
  write_file_atomically(file, text);
}

std::string plot_phase_diagram(const std::filesystem::path& scan_csv, const std::filesystem::path& lambda_crit_csv,
                               const std::filesystem::path& png, const std::filesystem::path& bifurcation_png,
                               const std::string& title, bool log_lambda) {
  AtomicFile output(png), bifurcation(bifurcation_png);
  std::vector<std::string> argv{plot_interpreter(), plot_scan_script().string(), "--scan", scan_csv.string(),
                                "--lambda-crit", lambda_crit_csv.string(), "--output",
                                output.temporary_path().string(), "--bifurcation",
                                bifurcation.temporary_path().string(), "--title", title};
  if (log_lambda) argv.push_back("--log-lambda");
  const ProcessOutcome run = run_process(argv, std::chrono::seconds(120));
  if (!run.succeeded()) {
    std::string why = run.output;
    const std::size_t end = why.find_last_not_of(" \n");
    if (end != std::string::npos) {
      why.resize(end + 1);
      why = why.substr(why.rfind('\n') == std::string::npos ? 0 : why.rfind('\n') + 1);
    }
    return argv[0] + " " + argv[1] + ": " + (why.empty() ? "failed" : why);
  }
  try {
    output.commit();
    bifurcation.commit();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace aggkit

#pragma once
// What a benchmark measured, as CSV rows for `bench/check`: every bench program records its figures with
//
//   aggkit::bench::Figures figures("dsmc_ballistic", argc, argv);
//   figures.add("particles=1e6 method=ar", "wall_seconds", 17.9, "s");
//
// Each add() appends one row to FOLDER/<bench>.csv, where FOLDER is $AGGKIT_BENCH_FIGURES or, by default,
// `figures/` beside the bench executable (build/bench/figures/). Columns:
//
//   date,bench,case,figure,value,unit,command
//
// `date` is UTC (ISO 8601), `case` names the parameters of the measurement, `command` is the command line
// that produced it. Rows accumulate: bench/check takes the latest row of each (bench, case, figure) and
// compares it with bench/results/standing.csv. A row is written with one write() of a complete line, so a killed
// bench leaves whole rows only.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <unistd.h>

namespace aggkit::bench {

class Figures {
 public:
  Figures(std::string bench, int argc, char** argv) : bench_(std::move(bench)) {
    for (int i = 0; i < argc; ++i) {
      if (i > 0) command_ += ' ';
      command_ += i == 0 ? "build/bench/" + std::filesystem::path(argv[0]).filename().string() : argv[i];
    }
    folder_ = figures_folder();
  }

  // Records one measured figure; a value that is not finite is recorded as "nan" (bench/check reports it).
  void add(const std::string& case_name, const std::string& figure, double value, const std::string& unit) const {
    std::error_code ignored;
    std::filesystem::create_directories(folder_, ignored);
    const auto file = folder_ / (bench_ + ".csv");
    const bool fresh = !std::filesystem::exists(file);
    std::ostringstream row;
    if (fresh) row << "date,bench,case,figure,value,unit,command\n";
    char number[64];
    std::snprintf(number, sizeof number, "%.9g", value);
    row << utc_now() << ',' << quoted(bench_) << ',' << quoted(case_name) << ',' << quoted(figure) << ',' << number
        << ',' << quoted(unit) << ',' << quoted(command_) << '\n';
    std::ofstream out(file, std::ios::app | std::ios::binary);
    const std::string text = row.str();
    out.write(text.data(), std::streamsize(text.size()));
    out.flush();
    if (!out) std::fprintf(stderr, "bench: could not append to %s\n", file.string().c_str());
  }

  const std::filesystem::path& folder() const { return folder_; }

  // A parameter value for a case name, shortest form ("0.01", "1e+06").
  static std::string text(double value) {
    char number[32];
    std::snprintf(number, sizeof number, "%g", value);
    return number;
  }

 private:
  static std::filesystem::path figures_folder() {
    if (const char* folder = std::getenv("AGGKIT_BENCH_FIGURES"); folder && *folder) return folder;
    std::error_code error;
    const auto exe = std::filesystem::read_symlink("/proc/self/exe", error);
    return (error ? std::filesystem::current_path() : exe.parent_path()) / "figures";
  }

  static std::string utc_now() {
    const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    std::tm utc{};
    gmtime_r(&now, &utc);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
    return text;
  }

  // RFC 4180 quoting: fields with a comma, quote or line break are quoted, quotes doubled.
  static std::string quoted(const std::string& field) {
    if (field.find_first_of(",\"\n\r") == std::string::npos) return field;
    std::string out = "\"";
    for (char c : field) {
      if (c == '"') out += '"';
      out += c;
    }
    return out + '"';
  }

  std::string bench_;
  std::string command_;
  std::filesystem::path folder_;
};

}  // namespace aggkit::bench

// Does DSMC reproduce the sustained oscillation of the kinetic equations ([Kalinov2022, Sec. 5.2])?
// Reads the series.csv files that `aggkit run bench/scenes/dsmc-oscillation.toml --out DIR` writes for the
// cvode and dsmc engines and classifies M0 and M2 of each over the last half of the run
// (analysis/oscillation.hpp); prints period and amplitude and their relative differences (target: 5 %).
//   bench_dsmc_oscillation DIR
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/oscillation.hpp"
#include "bench/figures.hpp"

namespace {

struct Series {
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;  // t first
};

Series read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  Series s;
  std::string line, cell;
  std::getline(in, line);
  std::stringstream header(line);
  while (std::getline(header, cell, ',')) s.names.push_back(cell);
  s.columns.resize(s.names.size());
  while (std::getline(in, line)) {
    std::stringstream row(line);
    for (std::size_t c = 0; c < s.names.size() && std::getline(row, cell, ','); ++c)
      s.columns[c].push_back(std::stod(cell));
  }
  return s;
}

const std::vector<double>& column(const Series& s, const std::string& name) {
  for (std::size_t c = 0; c < s.names.size(); ++c)
    if (s.names[c] == name) return s.columns[c];
  throw std::runtime_error("no column " + name);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR   (DIR from aggkit run bench/scenes/dsmc-oscillation.toml --out DIR)\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  const Series ode = read_csv(dir + "/cvode/series.csv");
  const Series dsmc = read_csv(dir + "/dsmc/series.csv");
  const aggkit::bench::Figures figures("dsmc_oscillation", argc, argv);
  std::printf("%-4s %-6s %-10s %10s %12s %12s %7s %9s\n", "obs", "engine", "regime", "period", "amplitude",
              "mean", "cycles", "converged");
  for (const char* name : {"M0", "M2"}) {
    aggkit::OscillationClassification c[2];
    const Series* runs[2] = {&ode, &dsmc};
    for (int e = 0; e < 2; ++e) {
      c[e] = aggkit::classify_oscillation(column(*runs[e], "t"), column(*runs[e], name));
      std::printf("%-4s %-6s %-10s %10.4f %12.5g %12.5g %7zu %9s\n", name, e == 0 ? "cvode" : "dsmc",
                  aggkit::to_string(c[e].regime).c_str(), c[e].period, c[e].amplitude, c[e].mean, c[e].cycles,
                  c[e].converged ? "yes" : "no");
    }
    std::printf("%-4s relative difference dsmc vs cvode: period %.2f %%, amplitude %.2f %%\n", name,
                100 * std::abs(c[1].period / c[0].period - 1), 100 * std::abs(c[1].amplitude / c[0].amplitude - 1));
    figures.add(std::string("a=0.95 lambda=0.01 ") + name, "period_relative_difference",
                std::abs(c[1].period / c[0].period - 1), "1");
    figures.add(std::string("a=0.95 lambda=0.01 ") + name, "amplitude_relative_difference",
                std::abs(c[1].amplitude / c[0].amplitude - 1), "1");
  }
  return 0;
}

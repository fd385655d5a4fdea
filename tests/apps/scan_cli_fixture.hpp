#pragma once
// What the `aggkit scan` command-line tests share: the command line, a coarse scan scene whose points take a
// tenth of a second each, and the scan.csv row of a point.
#include <filesystem>
#include <map>
#include <string>

#include "tests/apps/command_fixture.hpp"
#include "tests/validation/scene_fixture.hpp"

namespace aggkit::testing::scan {

namespace fs = std::filesystem;

// FFTW's measured plans may differ between processes (and so the last bits of a run); estimated plans
// make every process compute the same numbers.
inline const std::string environment = "AGGKIT_FFT_PLANNING=estimate";

inline std::string scan_command(const std::string& prefix, const fs::path& scene, const fs::path& out, bool plot = false) {
  std::string command = environment + " " + prefix + aggkit::testing::quoted(AGGKIT_CLI) + " scan " + aggkit::testing::quoted(scene.string()) +
                        " --out " + aggkit::testing::quoted(out.string());
  if (!plot) command += " --no-plot";
  return command;
}

using Outcome = aggkit::testing::CommandOutcome;
using aggkit::testing::mpirun;

inline Outcome run(const std::string& command, const fs::path& folder) { return aggkit::testing::run_command(command, folder); }

// A deliberately coarse graded grid (fixed-pivot shares, K = 8, r = 1.6: 34 classes) on which λ_crit(0.9) is
// 0.0027, against 0.0096 when converged: at λ = 0.004 the run relaxes and linear stability agrees on this
// grid, while on the refined grid (r = 1.3) the steady state is unstable (λ_crit > 0.0034 there) and the
// run barely decays (rate 5e-5, against 5e-3 on the coarse grid).
// λ = 0.012 relaxes on both; (0.9, 0.001) oscillates on both. Each run a tenth of a second.
inline const char* const coarse_scan = R"(
name = "coarse-scan"
[model]
kernel = { name = "brownian", a = 0.9 }
size = 1048576
grid = { resolved = 8, ratio = 1.6, scheme = "fixed-pivot" }
truncation = "drop"
[time]
end = 1000.0
every = 1.0
[scan]
a = [0.85, 0.9]
lambda = [0.001, 0.004, 0.012]
)";

// The scan.csv row of (a, λ), or an empty row.
inline std::map<std::string, std::string> scan_row(const fs::path& csv, double a, double lambda) {
  for (const auto& row : aggkit::testing::read_csv(csv))
    if (std::stod(row.at("a")) == a && std::stod(row.at("lambda")) == lambda) return row;
  return {};
}

}  // namespace aggkit::testing::scan

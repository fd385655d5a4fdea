// Scan throughput: points per minute of `aggkit scan` with 1 and 2 MPI ranks on the same scene, each into a
// fresh output folder (no resumed points), wall time including MPI start-up and the CSV/plot output.
//   build/bench/bench_scan_throughput build/aggkit validation/scenes/scan-brownian.toml [ranks...]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bench/figures.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s AGGKIT SCENE [RANKS...] (default ranks: 1 2)\n", argv[0]);
    return 2;
  }
  const std::string aggkit = argv[1], scene = argv[2];
  std::vector<int> ranks;
  for (int i = 3; i < argc; ++i) ranks.push_back(std::atoi(argv[i]));
  if (ranks.empty()) ranks = {1, 2};
  const aggkit::bench::Figures figures("scan_throughput", argc, argv);
  std::printf("%-6s %8s %10s %14s\n", "ranks", "points", "wall [s]", "points/minute");
  for (int k : ranks) {
    const std::filesystem::path out = std::filesystem::temp_directory_path() / ("aggkit-scan-throughput-" + std::to_string(k));
    std::filesystem::remove_all(out);
    const std::string command = "mpirun --allow-run-as-root --oversubscribe -np " + std::to_string(k) + " '" + aggkit +
                                "' scan '" + scene + "' --out '" + out.string() + "' --quiet --no-plot";
    const auto start = std::chrono::steady_clock::now();
    const int status = std::system(command.c_str());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (status != 0) {
      std::fprintf(stderr, "%s failed (status %d)\n", command.c_str(), status);
      return 1;
    }
    std::ifstream csv(out / "scan.csv");
    std::string line;
    long points = -1;  // the header
    while (std::getline(csv, line)) ++points;
    std::printf("%-6d %8ld %10.1f %14.1f\n", k, points, seconds, 60.0 * double(points) / seconds);
    figures.add(std::filesystem::path(scene).filename().string() + " ranks=" + std::to_string(k), "points_per_minute",
                60.0 * double(points) / seconds, "1/min");
    std::filesystem::remove_all(out);
  }
  return 0;
}

// Cost of one parallel phase on the worker pool (particle/common/worker_pool.hpp), the pattern of a DEM or TS
// step: RUNS runs of JOBS jobs of about WORK_US microseconds of arithmetic each, back to back, on 1 thread
// (plain loop) and on THREADS threads, alternated ROUNDS times. Prints per run: wall and CPU microseconds of
// each, the speed-up (wall) and the pool's overhead per run = wall − (serial wall)/THREADS. On a loaded
// machine only the CPU figures mean much (say so with the load average it prints).
//   bench_worker_pool [THREADS RUNS JOBS WORK_US ROUNDS]      defaults: 2 20000 8 10 3
// Records speedup and overhead_us_per_run (bench/figures.hpp).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "bench/figures.hpp"
#include "particle/common/worker_pool.hpp"

using namespace aggkit;

namespace {

// About `steps` dependent multiply-adds: work the compiler cannot remove (the result is kept).
double work(std::size_t steps, double seed) {
  double x = seed;
  for (std::size_t k = 0; k < steps; ++k) x = x * 0.999999 + 1e-7;
  return x;
}

struct Timing {
  double wall_us, cpu_us;
};

template <class Run>
Timing timed(std::size_t runs, Run&& run) {
  const auto w0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  for (std::size_t r = 0; r < runs; ++r) run();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  const double cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
  return {1e6 * wall / double(runs), 1e6 * cpu / double(runs)};
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t threads = argc > 1 ? std::size_t(std::atoi(argv[1])) : 2;
  const std::size_t runs = argc > 2 ? std::size_t(std::atof(argv[2])) : 20000;
  const std::size_t jobs = argc > 3 ? std::size_t(std::atoi(argv[3])) : 8;
  const double work_us = argc > 4 ? std::atof(argv[4]) : 10;
  const std::size_t rounds = argc > 5 ? std::size_t(std::atoi(argv[5])) : 3;
  if (threads < 2 || runs < 1 || jobs < 1 || !(work_us >= 0) || rounds < 1) {
    std::fprintf(stderr, "usage: %s [THREADS>=2 RUNS JOBS WORK_US ROUNDS]\n", argv[0]);
    return 2;
  }
  const bench::Figures figures("worker_pool", argc, argv);
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    char line[128] = {0};
    if (std::fgets(line, sizeof line, f)) std::printf("# load average: %s", line);
    std::fclose(f);
  }
  // Calibrate the job length: steps per CPU microsecond on this thread (CPU time: a loaded machine's
  // waits do not shorten the jobs).
  const std::size_t probe = 20000000;
  const std::clock_t c0 = std::clock();
  volatile double sink = work(probe, 1.0);
  const double per_us = double(probe) / (1e6 * double(std::clock() - c0) / CLOCKS_PER_SEC);
  const std::size_t steps = std::size_t(work_us * per_us);
  std::vector<double> out(jobs);
  auto job = [&](std::size_t k) { out[k] = work(steps, double(k)); };
  WorkerPool pool(threads);
  Timing best_serial{1e300, 1e300}, best_pool{1e300, 1e300};
  for (std::size_t round = 0; round < rounds; ++round) {
    const Timing serial = timed(runs, [&] {
      for (std::size_t k = 0; k < jobs; ++k) job(k);
    });
    const Timing parallel = timed(runs, [&] { pool.run(jobs, job); });
    std::printf("round %zu: per run serial wall %.2f us cpu %.2f us; %zu threads wall %.2f us cpu %.2f us\n", round, serial.wall_us,
                serial.cpu_us, threads, parallel.wall_us, parallel.cpu_us);
    if (serial.wall_us < best_serial.wall_us) best_serial = serial;
    if (parallel.wall_us < best_pool.wall_us) best_pool = parallel;
  }
  sink = sink + out[0];
  const double speedup = best_serial.wall_us / best_pool.wall_us;
  const double overhead = best_pool.wall_us - best_serial.wall_us / double(threads);
  std::printf("best: %zu jobs of %.1f us, serial %.2f us, %zu threads %.2f us per run: speed-up %.2f, overhead %.2f us per run\n", jobs,
              work_us, best_serial.wall_us, threads, best_pool.wall_us, speedup, overhead);
  const std::string name = "threads=" + std::to_string(threads) + " jobs=" + std::to_string(jobs) + " work_us=" + bench::Figures::text(work_us);
  figures.add(name, "speedup", speedup, "1");
  figures.add(name, "overhead_us_per_run", overhead, "us");
  return 0;
}

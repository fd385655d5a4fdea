// DEM self-gravity speed at the accuracy of interest: one force evaluation on N particles (unit masses,
// uniform in a ball of radius N^(1/3), ε = 1e-3), Barnes–Hut tree at several opening angles θ against the
// direct sum. The rms relative force error is measured on S = 2000 random particles against a plain double
// loop over all N partners (no tree, no tiling).
//   bench_dem_gravity N THETA1 [THETA2 ...]      prints per θ: seconds (1 thread) and rms relative error;
//                                                then the direct sum (1 thread) on min(N, 20000) particles:
//                                                seconds, unique pairs/s (N(N−1)/2 per evaluation) and
//                                                pair interactions/s (N(N−1): each pair acts on two particles)
// Records the figures for bench/check (bench/figures.hpp).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <vector>

#include "bench/figures.hpp"
#include "particle/dem/direct_gravity.hpp"
#include "particle/dem/gravity_tree.hpp"

using namespace aggkit;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<Vector3> ball(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const double radius = std::cbrt(double(n));
  std::vector<Vector3> x;
  while (x.size() < n) {
    const Vector3 p{u(rng), u(rng), u(rng)};
    if (dot(p, p) <= 1) x.push_back(radius * p);
  }
  return x;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s N THETA1 [THETA2 ...]\n", argv[0]);
    return 2;
  }
  const auto n = std::size_t(std::atof(argv[1]));
  const double G = 1, eps = 1e-3;
  const bench::Figures figures("dem_gravity", argc, argv);
  const std::vector<Vector3> x = ball(n, 1);
  const std::vector<double> m(n, 1.0);
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    char line[128] = {0};
    if (std::fgets(line, sizeof line, f)) std::printf("# load average: %s", line);
    std::fclose(f);
  }
  // Reference forces on S random particles by a plain loop.
  std::mt19937_64 rng(7);
  std::vector<std::size_t> sample;
  for (std::size_t k = 0; k < std::min<std::size_t>(2000, n); ++k) sample.push_back(rng() % n);
  std::vector<Vector3> reference;
  for (std::size_t i : sample) {
    Vector3 f{0, 0, 0};
    for (std::size_t j = 0; j < n; ++j) {
      const Vector3 d = x[j] - x[i];
      const double r2 = dot(d, d), r = std::sqrt(r2);
      if (r > 0) f = f + (G * m[i] * m[j] / (r * (r2 + eps * eps))) * d;
    }
    reference.push_back(f);
  }
  std::printf("# N %zu, uniform ball, rms relative error on %zu particles\n%8s %10s %10s %12s\n", n, sample.size(), "theta", "wall_s",
              "cpu_s", "rms_error");
  for (int k = 2; k < argc; ++k) {
    const double theta = std::atof(argv[k]);
    std::vector<Vector3> force(n, {0, 0, 0});
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    tree_gravity(x, m, G, eps, theta, 1, force);
    const double wall = seconds_since(t0), cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
    double sum = 0;
    for (std::size_t s = 0; s < sample.size(); ++s) {
      const Vector3 e = force[sample[s]] - reference[s];
      sum += dot(e, e) / dot(reference[s], reference[s]);
    }
    const double error = std::sqrt(sum / double(sample.size()));
    std::printf("%8.3f %10.3f %10.3f %12.3e\n", theta, wall, cpu, error);
    const std::string name = "N=" + bench::Figures::text(double(n)) + " theta=" + bench::Figures::text(theta);
    figures.add(name, "tree_wall_seconds", wall, "s");
    figures.add(name, "tree_cpu_seconds", cpu, "s");
    figures.add(name, "rms_relative_error", error, "1");
  }
  const std::size_t nd = std::min<std::size_t>(n, 20000);
  const std::vector<Vector3> xd(x.begin(), x.begin() + std::ptrdiff_t(nd));
  const std::vector<double> md(nd, 1.0);
  std::vector<Vector3> force(nd, {0, 0, 0});
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  direct_gravity(xd, md, G, eps, 1, force);
  const double wall = seconds_since(t0), cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
  const double pairs = double(nd) * double(nd - 1) / 2;
  std::printf("direct N %zu: wall_s %.3f cpu_s %.3f unique_pairs_per_s %.3g (cpu %.3g) interactions_per_s %.3g (cpu %.3g)\n", nd, wall,
              cpu, pairs / wall, pairs / cpu, 2 * pairs / wall, 2 * pairs / cpu);
  const std::string name = "N=" + bench::Figures::text(double(nd));
  figures.add(name, "direct_unique_pairs_per_s", pairs / wall, "1/s");
  figures.add(name, "direct_unique_pairs_per_cpu_s", pairs / cpu, "1/s");
  return 0;
}

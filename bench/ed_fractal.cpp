// Fractal dimension of the final aggregate against the volume fraction (2-D, reflecting walls, unit speed
// with uniform directions, as in [Degond2024, Sec. 4.1]; cf. [Gonzalez2011, Sec. 3.3]): mass–radius and
// box-counting dimensions (analysis/fractal_dimension.hpp) of the single final cluster, with fit errors;
// also N_c (α_R = 2.1).
//   bench_ed_fractal N SEEDS NU1 [NU2 ...]   prints one line per ν (means over SEEDS realizations)
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "analysis/fractal_dimension.hpp"
#include "analysis/shape.hpp"
#include "bench/ed_common.hpp"
#include "bench/figures.hpp"
#include "particle/ed/ed_configuration.hpp"

using namespace aggkit;

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s N SEEDS NU1 [NU2 ...]\n", argv[0]);
    return 2;
  }
  const auto n = std::size_t(std::atof(argv[1]));
  const int seeds = std::atoi(argv[2]);
  bench::print_load();
  std::printf("# N %zu, 2-D reflecting, %d realizations; means (spread = std of the realizations)\n", n, seeds);
  std::printf("%8s %10s %8s %8s %10s %8s %8s %8s\n", "nu", "D_mass", "spread", "fit_err", "D_box", "fit_err", "N_c", "run_s");
  const bench::Figures figures("ed_fractal", argc, argv);
  for (int k = 3; k < argc; ++k) {
    const double nu = std::atof(argv[k]);
    double dm = 0, dm2 = 0, em = 0, db = 0, eb = 0, nc = 0;
    int box_ok = 0;
    const auto start = std::chrono::steady_clock::now();
    for (int s = 0; s < seeds; ++s) {
      auto ed = bench::make_ed(2, n, nu, Boundary::reflecting, true, std::uint64_t(s + 1));
      ed.advance(1e30, 1);
      const auto points = ed.cluster_positions(ed.largest_cluster());
      const FractalFit mass = mass_radius_dimension(points, 2, ed.radius());
      const FractalFit box = box_counting_dimension(points, 2, ed.radius(), ed.box().side[0]);
      dm += mass.dimension / seeds;
      dm2 += mass.dimension * mass.dimension / seeds;
      em += mass.standard_error / seeds;
      if (std::isfinite(box.dimension)) {
        db += box.dimension;
        eb += box.standard_error;
        ++box_ok;
      }
      nc += relative_contacts(configuration(ed), 2.1) / seeds;
    }
    std::printf("%8g %10.3f %8.3f %8.3f %10.3f %8.3f %8.3f %8.1f\n", nu, dm, std::sqrt(std::max(0.0, dm2 - dm * dm)), em,
                box_ok ? db / box_ok : NAN, box_ok ? eb / box_ok : NAN, nc, bench::seconds_since(start));
    std::fflush(stdout);
    const std::string case_name = "dim=2 reflecting nu=" + bench::Figures::text(nu) + " N=" + bench::Figures::text(double(n)) +
                                  " realizations=" + std::to_string(seeds);
    figures.add(case_name, "mass_radius_dimension", dm, "1");
    figures.add(case_name, "box_counting_dimension", box_ok ? db / box_ok : NAN, "1");
    figures.add(case_name, "contacts", nc, "1");
  }
  bench::print_load();
}

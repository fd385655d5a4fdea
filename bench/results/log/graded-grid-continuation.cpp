// Continuation in (a, ln λ) from a known steady state: does a positive steady state exist at small a?
// A study kept with bench/results/log/graded-grid.md (not built by CMake). Build and run from the repository root:
//   g++ -O2 -std=c++20 -I. bench/results/log/graded-grid-continuation.cpp -o /tmp/cont -Lbuild/solvers -Lbuild/analysis
//       -laggkit_solvers -laggkit_analysis -Wl,-rpath,$PWD/build/solvers:$PWD/build/analysis
//   /tmp/cont K r N scheme steps a0 l0 a1 l1 ...   (e.g. 512 1.02 1.1e12 three-moment 6 0.6 1e-6 0.6 5.745e-8
//                                                   0.59 5.745e-8 0.59 2.5e-9 0.59 4e-11)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include "solvers/steady_state.hpp"
#include "solvers/stability.hpp"
#include "solvers/size_grid.hpp"
using namespace aggkit;
int main(int argc, char** argv) {
  // cont K r N scheme steps a0 l0 a1 l1 a2 l2 ...
  std::size_t K = atoi(argv[1]); double r = atof(argv[2]); double N = atof(argv[3]);
  GridScheme scheme = scheme_from_name(argv[4]); int steps = atoi(argv[5]);
  std::vector<double> way; for (int i = 6; i < argc; ++i) way.push_back(atof(argv[i]));
  AggregationModel m;
  m.size = std::size_t(N); m.truncation = Truncation::cutoff; m.initial = monodisperse(1);
  m.grid.resolved = K; m.grid.ratio = r; m.grid.scheme = scheme;
  std::vector<double> guess;
  for (std::size_t seg = 0; seg + 2 < way.size() || seg == 0; seg += 2)
  for (int s = (seg ? 1 : 0); s <= steps; ++s) {
    double a0 = way[seg], l0 = way[seg + 1], a1 = way.size() > seg + 2 ? way[seg + 2] : a0, l1 = way.size() > seg + 2 ? way[seg + 3] : l0;
    double f = steps ? double(s) / steps : 1.0;
    double a = a0 + f * (a1 - a0), lam = std::exp(std::log(l0) + f * (std::log(l1) - std::log(l0)));
    m.kernel = Kernel::brownian(a); m.lambda = ShatteringRate::constant(lam);
    SteadyStateResult st = solve_steady_state(m, {}, guess);
    { auto x = m.pivots(); std::size_t im = 0; for (std::size_t i = 0; i < st.n.size(); ++i) if (st.n[i] < st.n[im]) im = i;
      std::printf("   min entry at x=%.3g (n=%.3g)\n", x[im], st.n[im]); }
    if (!st.converged) { std::printf("a=%.4f lam=%.4g FAILED: %s\n", a, lam, st.note.c_str()); if (guess.empty()) return 1; continue; }
    guess = st.n;
    StabilityResult stab = analyse_stability(m, st.n, 8);
    auto p = rightmost_complex_pair(stab.rightmost);
    std::printf("a=%.4f lam=%.4g M0=%.6e newton=%d negmass=%.2e mostneg=%.2e pair=%.4e%+.4ei rightmost=%.4e\n", a, lam, [&]{double s=0; for(double v: st.n) s+=v; return s;}(), st.newton_iterations,
                st.negative_mass_fraction, st.most_negative_density, p.real(), p.imag(), stab.rightmost[0].real());
    std::fflush(stdout);
  }
}

// The callbacks every time stepper of the aggregation-shattering system shares (integration_problem.hpp).
#include "solvers/integration_problem.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace aggkit::integration {

int rhs(double t, N_Vector y, N_Vector ydot, void* data) {
  auto* p = static_cast<Problem*>(data);
  return guarded(p, [&] {
    p->rates->evaluate(t, view(y, p->N), view_mut(ydot, p->N));
    N_VGetArrayPointer(ydot)[p->N] = p->rates->leak_rate(t, view(y, p->N));
  });
}

// Projection onto the mass shell g·y = Σ k n_k + L = M. The defect d = g·y - M is removed by
// δ_i = -d w_i g_i / Σ_j w_j g_j² with w_i = S_i²/g_i^4 (S_i = rtol|y_i| + atol_i the error scale) on the
// components in the relative-tolerance regime (rtol|y_i| ≥ atol_i) and w_i = 0 on all others. Like the
// orthogonal projection in the error-weight metric it moves only what may move, and the extra 1/g^4
// keeps the correction on small sizes, where it changes M2 and M3 least. L is not corrected.
//
// Why the sizes below their absolute tolerance are left alone: they hold no information at the
// tolerance, but a correction there, however small (~1e-40 at rtol 1e-8), turns the exact zeros beyond
// the distribution's natural support into a tail spanning all N sizes. The fast right-hand side reads
// its active range and the decay rate of its tilted convolution off that tail (solvers/rates_fast.cpp),
// so the tilt collapses (θ ≈ ln(1e41)/N) and FFT round-off of ~1e-16 e^{-θ s} lands on sizes s ~ 10^3,
// below their tolerance floor, where CVODE accepts it. Weighted by k³ over thousands of sizes that junk
// shifted M3 by ~1e-6 at early times whatever rtol (constant kernel, N = 32768: 1.6e-6 … 7.4e-6 at
// rtol 1e-5 … 1e-8; bench/results/log/cvode-tolerance-proportionality.md). Restricted to the relative regime, the correction stays on the
// resolved sizes, the tail keeps its exact zeros, and the errors fall with rtol (tests/solvers/
// test_tolerance_proportionality.cpp). The defect itself is the Newton residual of the mass, so the
// resolved sizes absorb it at O(rtol) relative change.
void project_onto_mass_shell(const Problem& p, const double* y, double* correction, double* error) {
  const std::size_t size = p.N + 1;
  auto g = [&](std::size_t i) { return i < p.N ? p.sizes[i] : 1.0; };
  double mass = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < size; ++i) {
    // L itself is never corrected: it stays the integral of the leak rate (0 under cutoff).
    const double relative = p.rtol * std::abs(y[i]);
    const double scale = i == p.N || relative < p.abstol[i] ? 0.0 : relative + p.abstol[i];
    correction[i] = scale * scale / (g(i) * g(i) * g(i));  // w_i g_i
    mass += g(i) * y[i];
    norm += g(i) * correction[i];
  }
  if (!(norm > 0.0)) {  // nothing resolved (all sizes below their absolute tolerance): leave y as it is
    std::fill(correction, correction + size, 0.0);
    return;
  }
  if (error) {  // the local error estimate is projected the same way
    double error_mass = 0.0;
    for (std::size_t i = 0; i < size; ++i) error_mass += g(i) * error[i];
    for (std::size_t i = 0; i < size; ++i) error[i] -= correction[i] * error_mass / norm;
  }
  const double excess = (mass - p.mass) / norm;
  for (std::size_t i = 0; i < size; ++i) correction[i] *= -excess;
}

// Error weights. The error norm of CVODE and ARKODE is a root mean square over all N+1 components, so
// when most sizes are far-tail entries below their absolute tolerance the errors of the few sizes that
// matter are diluted by sqrt(N / active): at N = 2^17 the steady-state M0 was off by 2e-4 at rtol 1e-6.
// The weights 1/(rtol|y_i| + atol_i) are therefore scaled by sqrt((N+1)/A), A the number of components in
// the relative-tolerance regime (rtol|y_i| ≥ atol_i), which makes the norm an RMS over those.
int error_weights(N_Vector y, N_Vector weights, void* data) {
  auto* p = static_cast<Problem*>(data);
  const double* yy = N_VGetArrayPointer(y);
  double* w = N_VGetArrayPointer(weights);
  const std::size_t size = p->N + 1;
  std::size_t active = 0;
  for (std::size_t i = 0; i < size; ++i) {
    const double relative = p->rtol * std::abs(yy[i]);
    if (relative >= p->abstol[i]) ++active;
    w[i] = 1.0 / (relative + p->abstol[i]);
  }
  const double scale = std::sqrt(double(size) / double(std::max<std::size_t>(active, 1)));
  for (std::size_t i = 0; i < size; ++i) w[i] *= scale;
  return 0;
}

void error_handler(int code, const char* module, const char* function, char* message, void* data) {
  auto* p = static_cast<Problem*>(data);
  p->solver_message = std::string(module) + "/" + function + " (" + std::to_string(code) + "): " + message;
}

void check(int flag, const std::string& call, const Problem& problem) {
  if (flag < 0) {
    if (problem.error) std::rethrow_exception(problem.error);
    throw std::runtime_error(call + " failed with flag " + std::to_string(flag) +
                             (problem.solver_message.empty() ? "" : ": " + problem.solver_message));
  }
}

Context::Context() {
  if (SUNContext_Create(nullptr, &context) != 0) throw std::runtime_error("SUNContext_Create failed");
}
Context::~Context() { SUNContext_Free(&context); }

}  // namespace aggkit::integration

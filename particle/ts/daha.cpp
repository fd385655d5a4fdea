#include "particle/ts/daha.hpp"

#include <algorithm>
#include <cmath>

namespace aggkit {

namespace {

inline Vector3 separation(const std::vector<Vector3>& x, const DahaPair& p) {
  const Vector3& a = x[p.a];
  const Vector3& b = x[p.b];
  return {b[0] - a[0] + p.shift[0], b[1] - a[1] + p.shift[1], b[2] - a[2] + p.shift[2]};
}

}  // namespace

double link_potential(const DahaProblem& problem) {
  double w = 0;
  for (const DahaPair& p : problem.pairs)
    if (p.attract) w += 0.5 * dot(separation(problem.x, p), separation(problem.x, p));
  return w;
}

double largest_overlap(const DahaProblem& problem) {
  const double d2 = problem.contact * problem.contact;
  double worst = 0;
  for (const DahaPair& p : problem.pairs) {
    const Vector3 d = separation(problem.x, p);
    worst = std::max(worst, std::sqrt(std::max(0.0, d2 - dot(d, d))));
  }
  return worst;
}

DahaResult minimise(DahaProblem& problem, const DahaParameters& q) {
  const std::size_t n = problem.free;
  const std::size_t m = problem.pairs.size();
  const double contact2 = problem.contact * problem.contact;
  std::vector<Vector3>& x = problem.x;
  std::vector<Vector3> v(n, Vector3{0, 0, 0}), half(x.begin(), x.end()), force(n);
  std::vector<double> lambda(m), phi(m);
  std::size_t links = 0;
  for (const DahaPair& p : problem.pairs) links += p.attract ? 1 : 0;

  // φ per pair on positions `at`, the mean of √|φ| over the links (eq. 3.28, see the header) and the
  // largest √φ⁺ over every constrained pair.
  auto measure = [&](const std::vector<Vector3>& at, double& mean, double& worst) {
    double sum = 0;
    worst = 0;
    for (std::size_t k = 0; k < m; ++k) {
      const DahaPair& p = problem.pairs[k];
      const Vector3 d = separation(at, p);
      phi[k] = contact2 - dot(d, d);
      const double s = phi[k] > 0 ? std::sqrt(phi[k]) : 0.0;
      worst = std::max(worst, s);
      if (p.attract) sum += std::sqrt(std::abs(phi[k]));  // a link: overlap or gap (see the header)
    }
    mean = links ? sum / double(links) : 0.0;
  };

  const double damping = std::min(1.0, q.delta * q.c_bar);  // c̃ = δ c̄ (see the header)
  const double beta = q.delta * q.beta_bar;                   // β̃ = δ β̄
  DahaResult result;
  double mean = 0, worst = 0;
  measure(x, mean, worst);
  result.start_overlap = worst;
  // eq. 3.26, warm-started: a link starts at its contact multiplier ½ (see the header), so links that
  // already touch start in equilibrium and only the overlaps move spheres.
  for (std::size_t k = 0; k < m; ++k)
    lambda[k] = (problem.pairs[k].attract ? 0.5 : 0.0) + q.lambda0 * std::max(0.0, phi[k]);
  if (n == 0 || m == 0) {
    result.converged = true;
    result.mean_overlap = mean;
    result.max_overlap = worst;
    return result;
  }
  for (std::size_t r = 0; r < q.max_iterations; ++r) {
    // φ_A and φ_i^A of the current iterate X^r (measured at its end, or at the start).
    for (std::size_t i = 0; i < n; ++i) half[i] = x[i] + (0.5 * q.delta) * v[i];  // eq. 3.20
    std::fill(force.begin(), force.end(), Vector3{0, 0, 0});
    for (std::size_t k = 0; k < m; ++k) {
      const DahaPair& p = problem.pairs[k];
      const Vector3 d = separation(half, p);  // X_b − X_a
      const double ph = contact2 - dot(d, d);
      // −α(∇_a W + λ ∇_a φ) − γ φ λ ∇_a φ with ∇_a W = −d, ∇_a φ = 2d  [eq. 3.21]
      const double coefficient = (p.attract ? q.alpha : 0.0) - 2.0 * lambda[k] * (q.alpha + q.gamma * ph);
      const Vector3 f = coefficient * d;
      force[p.a] = force[p.a] + f;
      if (p.b < n) force[p.b] = force[p.b] - f;
    }
    double largest_move = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double speed = norm(v[i]);
      v[i] = (1.0 - damping) * (v[i] + force[i]);  // eqs. 3.21–3.22
      x[i] = half[i] + (0.5 * q.delta) * v[i];  // eq. 3.23
      // The move over the iteration, bounded by both half-drifts: |X^{r+1} − X^r| alone vanishes at the
      // turning points of an oscillation, where the forces are largest.
      largest_move = std::max(largest_move, 0.5 * q.delta * (speed + norm(v[i])));
    }
    measure(x, mean, worst);
    for (std::size_t k = 0; k < m; ++k) lambda[k] = std::max(0.0, lambda[k] + beta * phi[k]);  // eq. 3.24
    result.iterations = r + 1;
    if (largest_move <= q.eps_s && mean <= q.eps_c) {  // eqs. 3.27–3.28
      result.converged = true;
      break;
    }
  }
  result.mean_overlap = mean;
  result.max_overlap = worst;
  return result;
}

}  // namespace aggkit

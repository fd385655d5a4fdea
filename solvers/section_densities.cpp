// The density per unit size that a graded grid's numbers stand for (solvers/size_grid.hpp, "Densities").
//
// The numbers N_i are what the integer sizes k give their pivots under the scheme's shares S_i(k):
// N_i = Σ_k S_i(k) f(k). With f log-linear between pivots (the local form of an exponential tail), the
// f_i at the pivots are the fixed point of f ← f (N / P(f))^½, P(f)_i = Σ_k S_i(k) f(k), from f = N / Δ:
// a smooth correction (each pivot keeps its own size whole) that needs 100–200 sweeps for |N/P - 1| ≤ 1e-11
// everywhere; the half step keeps the steep far tail, where the neighbours' parts of P outweigh a pivot's
// own, from swinging back and forth. Where a pivot or a neighbour holds N ≤ 0 (the far tail at the
// integrator's tolerance) or no positive f fits, f keeps N / Δ.
//
// P is a fixed list of terms, built once: each interior size k of the interval (x_j, x_{j+1}) gives each
// pivot i of its stencil the coefficient S_i(k) at the fraction t = (k - x_j)/h of the interval; an
// interval of more than `summed` sizes gives instead the Euler–Maclaurin sum of each run of sizes with the
// same stencil: its integral by Gauss–Legendre quadrature (gsl_integration_glfixed), the half-values at the
// run's first and last size and (g'(last) - g'(first))/12 by one-sided differences; what is left is
// ~1/(720 h⁴) of the sum.
#include <gsl/gsl_integration.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "solvers/size_grid.hpp"

namespace aggkit {

namespace {

constexpr double summed = 64;         // intervals of up to this many sizes are summed size by size
constexpr std::size_t gauss_points = 12;
constexpr int sweeps = 400;
constexpr double converged = 1e-11;   // the largest |N / P(f) - 1| at the end

struct Term {
  std::size_t pivot;     // i
  std::size_t interval;  // j: f(k) from f_j and f_{j+1}
  double t;              // (k - x_j) / (x_{j+1} - x_j)
  double coefficient;    // S_i(k) (times the quadrature weight)
};

class Projection {
 public:
  Projection(std::span<const double> x, GridScheme scheme, std::size_t resolved)
      : x_(x), scheme_(scheme), resolved_(resolved),
        table_(gsl_integration_glfixed_table_alloc(gauss_points), gsl_integration_glfixed_table_free) {
    for (std::size_t j = 0; j + 1 < x_.size(); ++j) {
      const double first = x_[j] + 1.0, last = x_[j + 1] - 1.0;
      if (last < first) continue;  // neighbouring sizes: nothing between them
      if (last - first + 1.0 <= summed) {
        for (double k = first; k <= last; ++k) add(j, k, 1.0);
      } else {
        add_runs(j, first, last);
      }
    }
  }

  // P(f)_i: each pivot's own size plus the terms; f between x_j and x_{j+1} log-linear where both ends are
  // positive, else linear.
  std::vector<double> operator()(std::span<const double> f) const {
    std::vector<double> p(f.begin(), f.end()), slope(f.size(), 0.0);
    for (std::size_t j = 0; j + 1 < f.size(); ++j)
      slope[j] = f[j] > 0.0 && f[j + 1] > 0.0 ? std::log(f[j + 1] / f[j]) : NAN;
    for (const Term& term : terms_) {
      const double a = f[term.interval], s = slope[term.interval];
      const double value = std::isnan(s) ? a + term.t * (f[term.interval + 1] - a) : a * std::exp(term.t * s);
      p[term.pivot] += term.coefficient * value;
    }
    return p;
  }

 private:
  void add(std::size_t j, double k, double weight) {
    const PivotShare share = pivot_share(x_, k, scheme_, resolved_);
    const double t = (k - x_[j]) / (x_[j + 1] - x_[j]);
    for (int m = 0; m < share.count; ++m)
      terms_.push_back({share.first + std::size_t(m), j, t, weight * share.weight[m]});
  }

  // The sizes first..last of interval j in runs of one stencil (the nearest-three stencil changes at the
  // interval's midpoint), each summed by Euler–Maclaurin.
  void add_runs(std::size_t j, double first, double last) {
    const double middle = 0.5 * (x_[j] + x_[j + 1]);
    if (scheme_ == GridScheme::three_moment && first < middle && last >= middle) {
      const double below = std::ceil(middle) - 1.0;  // sizes k < middle are nearer x_j
      add_run(j, first, below);
      add_run(j, below + 1.0, last);
      return;
    }
    add_run(j, first, last);
  }

  void add_run(std::size_t j, double first, double last) {
    if (last - first < 2.0 * double(gauss_points)) {  // a short run (a split interval's end): size by size
      for (double k = first; k <= last; ++k) add(j, k, 1.0);
      return;
    }
    for (std::size_t node = 0; node < gauss_points; ++node) {
      double k = 0, weight = 0;
      gsl_integration_glfixed_point(first, last, node, &k, &weight, table_.get());
      add(j, k, weight);
    }
    add(j, first, 0.5);
    add(j, last, 0.5);
    // (g'(last) - g'(first)) / 12, the derivatives by second-order one-sided differences within the run
    // (its stencil's polynomial: beyond the run a split interval has the other stencil).
    const double d[3] = {1.5 / 12.0, -2.0 / 12.0, 0.5 / 12.0};
    for (int step = 0; step < 3; ++step) {
      add(j, last - step, d[step]);
      add(j, first + step, d[step]);
    }
  }

  std::span<const double> x_;
  GridScheme scheme_;
  std::size_t resolved_;
  std::unique_ptr<gsl_integration_glfixed_table, void (*)(gsl_integration_glfixed_table*)> table_;
  std::vector<Term> terms_;
};

}  // namespace

std::vector<double> section_densities(std::span<const double> x, std::span<const double> numbers, GridScheme scheme,
                                      std::size_t resolved) {
  const std::size_t M = numbers.size();
  const std::vector<double> width = pivot_widths(x);
  std::vector<double> f(M);
  for (std::size_t i = 0; i < M; ++i) f[i] = numbers[i] / width[i];
  if (x.size() < 2 || x.back() == double(x.size())) return f;  // the integers 1..N: f = N
  // Where a pivot or a neighbour holds N ≤ 0 (the far tail, at the integrator's tolerance, changes sign),
  // f keeps N / Δ: a fit through a sign change has no meaning.
  std::vector<char> fitted(M, 0);
  for (std::size_t i = 0; i < M; ++i)
    fitted[i] = numbers[i] > 0.0 && (i == 0 || numbers[i - 1] > 0.0) && (i + 1 == M || numbers[i + 1] > 0.0);
  const Projection project(x, scheme, resolved);
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    const std::vector<double> p = project(f);
    double largest = 0.0;
    for (std::size_t i = 0; i < M; ++i) {
      if (!fitted[i] || !(p[i] > 0.0)) continue;
      const double ratio = std::clamp(numbers[i] / p[i], 0.25, 4.0);
      f[i] *= std::sqrt(ratio);  // half steps: at a steep front the full one overshoots back and forth
      largest = std::max(largest, std::abs(ratio - 1.0));
      // A pivot whose neighbours alone give it more than its number (beside the sign changes of the far
      // tail) has no positive fit: f would fall without end. It keeps N / Δ.
      if (!(f[i] > 1e-3 * numbers[i] / width[i] && f[i] < 1e3 * numbers[i] / width[i])) {
        f[i] = numbers[i] / width[i];
        fitted[i] = 0;
      }
    }
    if (largest < converged) break;
  }
  return f;
}

}  // namespace aggkit

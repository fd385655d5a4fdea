// The density per unit size that a graded grid's numbers stand for (solvers/size_grid.hpp, "Densities").
//
// The numbers N_i are what the integer sizes k give their pivots under the scheme's shares S_i(k):
// N_i = Σ_k S_i(k) f(k). Each pivot's f_i is read from its own number alone, with the density over its
// stencil taken as the local exponential f_i e^{s_i (k - x_i)} (the local form of an exponential tail):
// f_i = N_i / D_i(s_i), D_i(s) = Σ_k S_i(k) e^{s (k - x_i)}, and s_i the log-slope between the neighbours'
// densities, iterated to the fixed point from f = N / Δ (15–65 sweeps on the constant kernel's densities at
// r = 1.1 … 1.0125; convergence is judged on the numbers above 1e-15 of the largest: far below, at the
// integrator's round-off, the slopes between neighbours swing from sweep to sweep by up to 1e-3 without settling,
// and that swing had kept r = 1.025 from converging in 200 sweeps). An exponential density is given
// back exactly. Why not fit all numbers at once (a density log-linear between pivots with P(f) = N): that
// inversion takes the sectional dynamics' own ripple in the numbers at the spacing jumps of the integer
// pivots (0.7–0.9 % at r = 1.025, constant kernel) and doubles it in the densities (1.70 %), while the local
// reading keeps it at the ripple (0.85 %). Where a pivot or a neighbour holds N ≤ 0 (the far tail at the
// integrator's tolerance) or the reading leaves (1e-3, 1e3) × N / Δ, f keeps N / Δ.
//
// D_i is a fixed list of terms, built once: each interior size k of the interval (x_j, x_{j+1}) gives each
// pivot i of its stencil the coefficient S_i(k) at the offset k - x_i; an interval of more than `summed`
// sizes gives instead the Euler–Maclaurin sum of each run of sizes with the same stencil: its integral by
// Gauss–Legendre quadrature (gsl_integration_glfixed), the half-values at the run's first and last size and
// (g'(last) - g'(first))/12 by one-sided differences; what is left is ~1/(720 h⁴) of the sum.
#include <gsl/gsl_integration.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "solvers/size_grid.hpp"

namespace aggkit {

namespace {

constexpr double summed = 64;         // intervals of up to this many sizes are summed size by size
constexpr std::size_t gauss_points = 12;
constexpr int sweeps = 200;
constexpr double converged = 1e-12;   // the largest relative change of f in the last sweep (numbers judged)
constexpr double judged = 1e-15;      // of the largest number: the numbers whose f must have converged

struct Term {
  std::size_t pivot;     // i
  double offset;         // k - x_i
  double coefficient;    // S_i(k) (times the quadrature weight)
};

class LocalSums {
 public:
  LocalSums(std::span<const double> x, GridScheme scheme, std::size_t resolved)
      : x_(x), scheme_(scheme), resolved_(resolved),
        table_(gsl_integration_glfixed_table_alloc(gauss_points), gsl_integration_glfixed_table_free) {
    for (std::size_t j = 0; j + 1 < x_.size(); ++j) {
      const double first = x_[j] + 1.0, last = x_[j + 1] - 1.0;
      if (last < first) continue;  // neighbouring sizes: nothing between them
      if (last - first + 1.0 <= summed) {
        for (double k = first; k <= last; ++k) add(k, 1.0);
      } else {
        add_runs(j, first, last);
      }
    }
  }

  // D_i(s_i) for every pivot: its own size plus the terms.
  std::vector<double> operator()(std::span<const double> slope) const {
    std::vector<double> d(slope.size(), 1.0);
    for (const Term& term : terms_) d[term.pivot] += term.coefficient * std::exp(slope[term.pivot] * term.offset);
    return d;
  }

 private:
  void add(double k, double weight) {
    const PivotShare share = pivot_share(x_, k, scheme_, resolved_);
    for (int m = 0; m < share.count; ++m) {
      const std::size_t i = share.first + std::size_t(m);
      terms_.push_back({i, k - x_[i], weight * share.weight[m]});
    }
  }

  // The sizes first..last of interval j in runs of one stencil (the nearest-three stencil changes at the
  // interval's midpoint), each summed by Euler–Maclaurin.
  void add_runs(std::size_t j, double first, double last) {
    const double middle = 0.5 * (x_[j] + x_[j + 1]);
    if (scheme_ == GridScheme::three_moment && first < middle && last >= middle) {
      const double below = std::ceil(middle) - 1.0;  // sizes k < middle are nearer x_j
      add_run(first, below);
      add_run(below + 1.0, last);
      return;
    }
    add_run(first, last);
  }

  void add_run(double first, double last) {
    if (last - first < 2.0 * double(gauss_points)) {  // a short run (a split interval's end): size by size
      for (double k = first; k <= last; ++k) add(k, 1.0);
      return;
    }
    for (std::size_t node = 0; node < gauss_points; ++node) {
      double k = 0, weight = 0;
      gsl_integration_glfixed_point(first, last, node, &k, &weight, table_.get());
      add(k, weight);
    }
    add(first, 0.5);
    add(last, 0.5);
    // (g'(last) - g'(first)) / 12, the derivatives by second-order one-sided differences within the run
    // (its stencil's polynomial: beyond the run a split interval has the other stencil).
    const double d[3] = {1.5 / 12.0, -2.0 / 12.0, 0.5 / 12.0};
    for (int step = 0; step < 3; ++step) {
      add(last - step, d[step]);
      add(first + step, d[step]);
    }
  }

  std::span<const double> x_;
  GridScheme scheme_;
  std::size_t resolved_;
  std::unique_ptr<gsl_integration_glfixed_table, void (*)(gsl_integration_glfixed_table*)> table_;
  std::vector<Term> terms_;
};

// The log-slope of f at pivot i: between its neighbours, one-sided at the ends or beside an f ≤ 0; 0 where
// neither side has two positive values.
double log_slope(std::span<const double> x, std::span<const double> f, std::size_t i) {
  const std::size_t below = i > 0 && f[i - 1] > 0.0 ? i - 1 : i;
  const std::size_t above = i + 1 < f.size() && f[i + 1] > 0.0 ? i + 1 : i;
  if (below == above || !(f[below] > 0.0) || !(f[above] > 0.0)) return 0.0;
  return std::log(f[above] / f[below]) / (x[above] - x[below]);
}

}  // namespace

std::vector<double> section_densities(std::span<const double> x, std::span<const double> numbers, GridScheme scheme,
                                      std::size_t resolved) {
  const std::size_t M = numbers.size();
  const std::vector<double> width = pivot_widths(x);
  std::vector<double> f(M);
  for (std::size_t i = 0; i < M; ++i) f[i] = numbers[i] / width[i];
  if (x.size() < 2 || x.back() == double(x.size())) return f;  // the integers 1..N: f = N
  // Where a pivot or a neighbour holds N ≤ 0 (the far tail, at the integrator's tolerance, changes sign),
  // f keeps N / Δ: a reading through a sign change has no meaning.
  std::vector<char> fitted(M, 0);
  for (std::size_t i = 0; i < M; ++i)
    fitted[i] = numbers[i] > 0.0 && (i == 0 || numbers[i - 1] > 0.0) && (i + 1 == M || numbers[i + 1] > 0.0);
  const LocalSums sums(x, scheme, resolved);
  const double judged_number = judged * *std::max_element(numbers.begin(), numbers.end());
  std::vector<double> slope(M, 0.0);
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    for (std::size_t i = 0; i < M; ++i) slope[i] = log_slope(x, f, i);
    const std::vector<double> d = sums(slope);
    double largest = 0.0;
    for (std::size_t i = 0; i < M; ++i) {
      if (!fitted[i]) continue;
      const double plain = numbers[i] / width[i], next = numbers[i] / d[i];
      // A reading far from N / Δ (the steep far tail, where the neighbours' slope swings) has no meaning.
      if (!(next > 1e-3 * plain && next < 1e3 * plain)) {
        f[i] = plain;
        fitted[i] = 0;
        continue;
      }
      if (numbers[i] >= judged_number) largest = std::max(largest, std::abs(next / f[i] - 1.0));
      f[i] = next;
    }
    if (largest < converged) break;
  }
  return f;
}

}  // namespace aggkit

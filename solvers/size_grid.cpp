#include "solvers/size_grid.hpp"

#include <gsl/gsl_multifit.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "analysis/input_error.hpp"

namespace aggkit {

const char* scheme_name(GridScheme scheme) {
  switch (scheme) {
    case GridScheme::four_moment: return "four-moment";
    case GridScheme::three_moment: return "three-moment";
    case GridScheme::fixed_pivot: break;
  }
  return "fixed-pivot";
}

GridScheme scheme_from_name(const std::string& name) {
  SizeGrid grid;
  check_option(*find_option(size_grid_option_rows().table(), "scheme"), name, "grid.scheme");
  size_grid_option_rows().apply(nlohmann::json{{"scheme", name}}, grid, "grid");
  return grid.scheme;
}

const OptionRows<SizeGrid>& size_grid_option_rows() {
  using B = Bind<SizeGrid>;
  static const std::vector<std::pair<std::string, GridScheme>> schemes = [] {
    std::vector<std::pair<std::string, GridScheme>> named;
    for (GridScheme scheme : {GridScheme::four_moment, GridScheme::three_moment, GridScheme::fixed_pivot})
      named.emplace_back(scheme_name(scheme), scheme);
    return named;
  }();
  static const OptionRows<SizeGrid> rows{{
      B::required(B::integer("resolved", &SizeGrid::resolved, at_least(2), "K: sizes 1..K one by one")),
      B::required(B::number("ratio", &SizeGrid::ratio, closed(1.0, 4.0), "r: the pivots beyond K grow by this ratio")),
      B::word("scheme", &SizeGrid::scheme, schemes, "how an aggregate between two pivots is shared"),
  }};
  return rows;
}

void SizeGrid::validate() const {
  if (!uniform()) size_grid_option_rows().check(*this, "grid");
}

std::string SizeGrid::describe() const {
  if (uniform()) return "uniform";
  char text[96];
  if (scheme == GridScheme::four_moment) std::snprintf(text, sizeof text, "graded(K=%zu, r=%.10g)", resolved, ratio);
  else std::snprintf(text, sizeof text, "graded(K=%zu, r=%.10g, %s)", resolved, ratio, scheme_name(scheme));
  return text;
}

std::size_t SizeGrid::largest_size() const { return uniform() ? 100'000'000 : std::size_t(1) << 62; }

SizeGrid SizeGrid::refined() const {
  SizeGrid finer = *this;
  if (!uniform()) finer.ratio = 1.0 + 0.5 * (ratio - 1.0);
  return finer;
}

std::vector<double> grid_pivots(const SizeGrid& grid, std::size_t N) {
  std::vector<double> x;
  const double last = double(N);
  if (grid.uniform()) {
    x.resize(N);
    for (std::size_t k = 0; k < N; ++k) x[k] = double(k + 1);
    return x;
  }
  grid.validate();
  const std::size_t K = std::min(grid.resolved, N);
  for (std::size_t k = 1; k <= K; ++k) x.push_back(double(k));
  constexpr std::size_t most = 10'000'000;  // r so close to 1 that the grid is as long as the uniform one
  while (x.back() < last) {
    if (x.size() >= most)
      throw InputError("grid.ratio", format_value(grid.ratio),
                       "a ratio giving at most " + std::to_string(most) + " classes up to N = " + std::to_string(N));
    // Integer pivots as long as doubles hold integers exactly (2^53); the next pivot at least one size on.
    double next = std::max(x.back() + 1.0, std::round(x.back() * grid.ratio));
    x.push_back(std::min(next, last));
  }
  return x;
}

std::vector<double> pivot_widths(std::span<const double> x) {
  const std::size_t M = x.size();
  std::vector<double> width(M, 1.0);
  for (std::size_t i = 0; i < M; ++i) {
    const double below = i > 0 ? x[i - 1] : 0.0;
    const double above = i + 1 < M ? x[i + 1] : (M > 1 ? 2.0 * x[i] - x[i - 1] : x[i] + 1.0);
    width[i] = 0.5 * (above - below);
  }
  return width;
}

std::pair<std::size_t, double> fixed_pivot_share(std::span<const double> x, double v) {
  const std::size_t M = x.size();
  if (v > x[M - 1]) return {M, 0.0};
  // p: the last pivot with x_p ≤ v.
  const std::size_t p = std::size_t(std::upper_bound(x.begin(), x.end(), v) - x.begin()) - 1;
  if (x[p] == v || p + 1 == M) return {p, 1.0};
  return {p, (x[p + 1] - v) / (x[p + 1] - x[p])};
}

namespace {

// The Lagrange weights of v on the pivots x_first .. x_first+count-1: Σ w_m x_m^p = v^p for p < count.
PivotShare lagrange_share(std::span<const double> x, double v, std::size_t first, int count) {
  PivotShare share;
  share.first = first;
  share.count = count;
  for (int m = 0; m < count; ++m) {
    double w = 1.0;
    for (int l = 0; l < count; ++l)
      if (l != m) w *= (v - x[first + l]) / (x[first + m] - x[first + l]);
    share.weight[m] = w;
  }
  return share;
}

}  // namespace

PivotShare pivot_share(std::span<const double> x, double v, GridScheme scheme, std::size_t resolved) {
  const std::size_t M = x.size();
  const auto [p, eta] = fixed_pivot_share(x, v);
  PivotShare share;
  share.first = p;
  if (p >= M || eta == 1.0) return share;  // beyond N, or on a pivot
  share.count = 2;
  share.weight[0] = eta;
  share.weight[1] = 1.0 - eta;
  if (scheme == GridScheme::fixed_pivot || M < 3) return share;
  // Below x_K the unit spacing jumps to the sections' (x_{K+1} - x_K ≫ 1 at coarse r), and a stencil
  // across the jump gives its far pivot a large negative share: just above x_K the stencil looks forward.
  if (scheme == GridScheme::four_moment && M >= 4) {
    // x_{p-1} .. x_{p+2}: the interval of v in the middle.
    std::size_t s = p > 0 ? p - 1 : p;
    if (s + 1 < resolved) s = p;
    if (s + 3 >= M) s = M - 4;
    if (s + 1 >= resolved) return lagrange_share(x, v, s, 4);
  }
  // The nearest three pivots: x_{p-1}, x_p, x_{p+1} when v is nearer x_p, else x_p, x_{p+1}, x_{p+2}.
  std::size_t q = v - x[p] < x[p + 1] - v && p > 0 ? p - 1 : p;
  if (q + 1 < resolved) q = p;
  if (q + 2 >= M) q = M - 3;
  if (q + 1 < resolved) return share;  // fewer than two sections: the fixed-pivot pair
  return lagrange_share(x, v, q, 3);
}

std::vector<double> to_grid(std::span<const double> x, std::span<const double> per_size) {
  std::vector<double> n(x.size(), 0.0);
  for (std::size_t k = 0; k < per_size.size(); ++k) {
    if (per_size[k] == 0.0) continue;
    const auto [p, share] = fixed_pivot_share(x, double(k + 1));
    if (p >= x.size()) continue;  // beyond N (model.validate refuses such tables)
    n[p] += share * per_size[k];
    if (share < 1.0) n[p + 1] += (1.0 - share) * per_size[k];
  }
  return n;
}

namespace {

// ln f = a + b ln(x/s) + c x/s (c clamped to ≤ 0), the unweighted least-squares fit (gsl_multifit_linear) of
// the rows given, with the sizes scaled by s for a well-conditioned fit: the form of a steady tail, a power
// law with an exponential cut-off. nullopt where the fit fails or is not finite.
struct TailFit {
  double a = 0, b = 0, c = 0, scale = 1;
  double operator()(double x) const { return std::exp(a + b * std::log(x / scale) + c * x / scale); }
};

std::optional<TailFit> fit_tail(std::span<const double> x, std::span<const double> f, double scale) {
  const std::size_t m = x.size();
  gsl_matrix* X = gsl_matrix_alloc(m, 3);
  gsl_vector* y = gsl_vector_alloc(m);
  gsl_vector* c = gsl_vector_alloc(3);
  gsl_matrix* cov = gsl_matrix_alloc(3, 3);
  gsl_multifit_linear_workspace* work = gsl_multifit_linear_alloc(m, 3);
  for (std::size_t r = 0; r < m; ++r) {
    gsl_matrix_set(X, r, 0, 1.0);
    gsl_matrix_set(X, r, 1, std::log(x[r] / scale));
    gsl_matrix_set(X, r, 2, x[r] / scale);
    gsl_vector_set(y, r, std::log(f[r]));
  }
  double chisq = 0;
  const int status = gsl_multifit_linear(X, y, c, cov, &chisq, work);
  TailFit fit{gsl_vector_get(c, 0), gsl_vector_get(c, 1), std::min(0.0, gsl_vector_get(c, 2)), scale};
  gsl_multifit_linear_free(work);
  gsl_matrix_free(cov);
  gsl_vector_free(c);
  gsl_vector_free(y);
  gsl_matrix_free(X);
  if (status != 0 || !std::isfinite(fit.a) || !std::isfinite(fit.b) || !std::isfinite(fit.c)) return std::nullopt;
  return fit;
}

}  // namespace

std::vector<double> extend_steady_state(std::span<const double> coarse, std::size_t N) {
  const std::size_t Nc = coarse.size(), keep = std::min(Nc / 2, N), first = Nc / 8 + 1;
  std::vector<double> n(N, 0.0);
  std::copy(coarse.begin(), coarse.begin() + std::ptrdiff_t(keep), n.begin());
  if (keep >= N || keep < first + 3) return n;
  std::vector<double> k, f;
  for (std::size_t i = first; i <= keep; ++i) {
    if (!(coarse[i - 1] > 0.0)) return n;  // no positive tail to fit: zeros beyond
    k.push_back(double(i));
    f.push_back(coarse[i - 1]);
  }
  const auto fit = fit_tail(k, f, double(keep));
  if (!fit) return n;
  for (std::size_t i = keep + 1; i <= N; ++i) n[i - 1] = (*fit)(double(i));  // underflows to 0 far out: fine
  return n;
}

std::vector<double> regrid(std::span<const double> from, std::span<const double> state, std::span<const double> to) {
  const std::size_t Ma = from.size();
  const std::vector<double> wa = pivot_widths(from), wb = pivot_widths(to);
  std::vector<double> f(Ma);
  for (std::size_t i = 0; i < Ma; ++i) f[i] = state[i] / wa[i];
  // Tail fit ln f = a + b ln(x/x_h) + c x/x_h over x_M/8 < x ≤ x_M/2 (x_h = x_M/2), as
  // extend_steady_state does on the uniform grid (above).
  const double xh = 0.5 * from[Ma - 1];
  std::optional<TailFit> fit;
  {
    std::vector<double> x, g;
    for (std::size_t i = 0; i < Ma; ++i)
      if (from[i] > xh / 4.0 && from[i] <= xh && f[i] > 0.0) x.push_back(from[i]), g.push_back(f[i]);
    if (x.size() >= 4) fit = fit_tail(x, g, xh);
  }
  std::vector<double> out(to.size(), 0.0);
  for (std::size_t j = 0; j < to.size(); ++j) {
    const double x = to[j];
    double density = 0.0;
    if (x > xh && fit) {
      density = (*fit)(x);
    } else if (x <= from[Ma - 1]) {
      const std::size_t i = std::size_t(std::upper_bound(from.begin(), from.end(), x) - from.begin());
      if (i == 0) {
        density = f[0];
      } else if (i == Ma || from[i - 1] == x) {
        density = f[i - 1];
      } else {
        const double t = std::log(x / from[i - 1]) / std::log(from[i] / from[i - 1]);
        density = f[i - 1] > 0.0 && f[i] > 0.0 ? std::exp((1 - t) * std::log(f[i - 1]) + t * std::log(f[i]))
                                               : (1 - t) * f[i - 1] + t * f[i];
      }
    }
    out[j] = density * wb[j];
  }
  return out;
}

}  // namespace aggkit

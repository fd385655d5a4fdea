#include "solvers/sectional_far_field.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace aggkit {

SectionalFarField::SectionalFarField(std::span<const double> x, const Kernel::Factors& factors)
    : x_(x.begin(), x.end()), features_(factors.features.size()) {
  if (features_ == 0 || features_ > max_features)
    throw std::invalid_argument("SectionalFarField: " + std::to_string(features_) + " kernel factors (1 to " +
                                std::to_string(max_features) + " allowed)");
  const std::size_t M = x_.size(), P = features_;
  h_.assign(M, 0.0);
  for (std::size_t j = 0; j + 1 < M; ++j) h_[j] = x_[j + 1] - x_[j];
  phi_.resize(M * P);
  g_.assign(M * P, 0.0);
  power_.resize(M * max_stencil);
  for (std::size_t i = 0; i < M; ++i) {
    for (std::size_t p = 0; p < P; ++p) phi_[i * P + p] = factors.features[p](x_[i]);
    double xd = 1.0;
    for (std::size_t d = 0; d < max_stencil; ++d, xd *= x_[i]) power_[i * max_stencil + d] = xd;
  }
  for (std::size_t j = 0; j < M; ++j)
    for (std::size_t p = 0; p < P; ++p)
      for (std::size_t q = 0; q < P; ++q) g_[j * P + p] += factors.coupling[p][q] * phi_[j * P + q];
  first_.assign(M, 0);
  width_.assign(M, 0);
  count_.assign(M, 0);
  poly_.assign(M, {});
}

void SectionalFarField::set_stencil(std::size_t j, std::size_t first, std::size_t width) {
  if (j + 1 >= x_.size() || width == 0 || width > max_stencil || first + width > x_.size())
    throw std::invalid_argument("SectionalFarField: stencil out of range");
  first_[j] = std::uint32_t(first);
  width_[j] = std::uint32_t(width);
  // L_m(x_j + h_j t) = Π_{l≠m} (t + α_l) / β_ml, α_l = (x_j − y_l)/h_j, β_ml = (y_m − y_l)/h_j, y the stencil's
  // pivots: the product expanded term by term (coefficients of t^0 .. t^{width−1}).
  const double h = h_[j];
  auto& c = poly_[j];
  c.fill(0.0);
  for (std::size_t m = 0; m < width; ++m) {
    double* cm = c.data() + m * max_stencil;
    cm[0] = 1.0;
    std::size_t degree = 0;
    for (std::size_t l = 0; l < width; ++l) {
      if (l == m) continue;
      const double alpha = (x_[j] - x_[first + l]) / h, beta = (x_[first + m] - x_[first + l]) / h;
      ++degree;
      for (std::size_t d = degree; d > 0; --d) cm[d] = (cm[d - 1] + alpha * cm[d]) / beta;
      cm[0] = alpha * cm[0] / beta;
    }
  }
}

double SectionalFarField::share(std::size_t j, std::size_t m, double s) const {
  const double t = s / h_[j];
  const double* c = poly_[j].data() + m * max_stencil;
  return c[0] + t * (c[1] + t * (c[2] + t * c[3]));
}

void SectionalFarField::set_counts(std::vector<std::uint32_t> count) {
  if (count.size() != x_.size()) throw std::invalid_argument("SectionalFarField: one count per class");
  std::uint32_t most = 0;
  for (std::size_t j = 0; j < count.size(); ++j) {
    if (count[j] > 0 && (count[j] > j || count[j] < most || width_[j] == 0))
      throw std::invalid_argument("SectionalFarField: counts must be nondecreasing (0: none), at most j, on set stencils");
    most = std::max(most, count[j]);
  }
  count_ = std::move(count);
}

std::size_t SectionalFarField::pairs() const {
  std::size_t total = 0;
  for (std::uint32_t c : count_) total += c;
  return total;
}

void SectionalFarField::accumulate(double lambda, std::span<const double> u, std::span<const double> v, double scale,
                                   double* gain, double& monomers, Scratch& scratch) const {
  const std::size_t M = x_.size(), P = features_, D = max_stencil;
  scratch.bucket_u.assign((M + 1) * P, 0.0);
  scratch.bucket_v.assign((M + 1) * P, 0.0);
  double U[max_features * max_stencil] = {}, V[max_features * max_stencil] = {};
  std::size_t filled = 0;
  for (std::size_t j = 0; j < M; ++j) {
    const std::size_t I = count_[j];
    if (I == 0) continue;
    for (; filled < I; ++filled) {  // the prefix sums U_pd, V_pd up to I_j
      const double ui = u[filled], vi = v[filled];
      for (std::size_t p = 0; p < P; ++p) {
        const double f = phi_[filled * P + p];
        for (std::size_t d = 0; d < D; ++d) {
          const double a = f * power_[filled * D + d];
          U[p * D + d] += a * ui;
          V[p * D + d] += a * vi;
        }
      }
    }
    double R[max_stencil];
    for (std::size_t d = 0; d < D; ++d) {
      double s = 0.0;
      for (std::size_t p = 0; p < P; ++p) s += g_[j * P + p] * (v[j] * U[p * D + d] + u[j] * V[p * D + d]);
      R[d] = scale * s;
    }
    gain[j] -= R[0] + lambda * R[0];
    monomers += R[1] + x_[j] * R[0];
    double scaled[max_stencil];  // R_jd / h_j^d
    double hp = 1.0;
    for (std::size_t d = 0; d < D; ++d, hp *= h_[j]) scaled[d] = R[d] / hp;
    const double* c = poly_[j].data();
    for (std::size_t m = 0; m < width_[j]; ++m)
      gain[first_[j] + m] += c[m * D] * scaled[0] + c[m * D + 1] * scaled[1] + c[m * D + 2] * scaled[2] +
                             c[m * D + 3] * scaled[3];
    for (std::size_t p = 0; p < P; ++p) {
      scratch.bucket_u[I * P + p] += g_[j * P + p] * u[j];
      scratch.bucket_v[I * P + p] += g_[j * P + p] * v[j];
    }
  }
  if (filled == 0) return;
  // The smaller partners' losses: class i is a far partner of the columns j with I_j > i, those bucketed above i.
  double Qu[max_features] = {}, Qv[max_features] = {};
  for (std::size_t i = M; i-- > 0;) {
    double L = 0.0;
    for (std::size_t p = 0; p < P; ++p) {
      Qu[p] += scratch.bucket_u[(i + 1) * P + p];
      Qv[p] += scratch.bucket_v[(i + 1) * P + p];
      L += phi_[i * P + p] * (u[i] * Qv[p] + v[i] * Qu[p]);
    }
    L *= scale;
    gain[i] -= L + lambda * L;
  }
}

}  // namespace aggkit

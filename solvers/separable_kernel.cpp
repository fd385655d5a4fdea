#include "solvers/separable_kernel.hpp"

#include <cmath>

namespace aggkit {

namespace {
// acc[f] += c a[f] b[f] with the arithmetic written out: std::complex multiplication checks for
// NaN/inf (C99 Annex G) and is several times slower in this innermost loop.
void multiply_add(double c, const std::complex<double>* a, const std::complex<double>* b, std::size_t m,
                  std::complex<double>* acc) {
  const double* x = reinterpret_cast<const double*>(a);
  const double* y = reinterpret_cast<const double*>(b);
  double* z = reinterpret_cast<double*>(acc);
  for (std::size_t f = 0; f < m; ++f) {
    const double re = x[2 * f] * y[2 * f] - x[2 * f + 1] * y[2 * f + 1];
    const double im = x[2 * f] * y[2 * f + 1] + x[2 * f + 1] * y[2 * f];
    z[2 * f] += c * re;
    z[2 * f + 1] += c * im;
  }
}
}  // namespace

SeparableKernel::SeparableKernel(SeparableForm form, std::size_t N)
    : form_(std::move(form)), size_(N), work_(N), partial_(form_.rank(), std::vector<double>(N + 2, 0.0)) {
  for (std::size_t p = 0; p < rank(); ++p)
    for (std::size_t q = 0; q < rank(); ++q)
      if (form_.coupling[p][q] != 0.0) couplings_.push_back({p, q, form_.coupling[p][q]});
}

double SeparableKernel::entry(std::size_t i, std::size_t j) const {
  double sum = 0.0;
  for (const auto& [p, q, c] : couplings_) sum += c * form_.features[p][i - 1] * form_.features[q][j - 1];
  return sum;
}

void SeparableKernel::collision_rates(std::span<const double> y, std::size_t active, bool cutoff,
                                      std::vector<double>& rate, std::size_t rows) {
  std::fill(rate.begin(), rate.end(), 0.0);
  if (rows == 0) rows = active;
  if (!cutoff) {  // c_k = Σ_pq C_pq φ_p(k) m_q, m_q = Σ_j φ_q(j) y_j
    moments_.assign(rank(), 0.0);
    for (std::size_t q = 0; q < rank(); ++q) {
      const double* phi = form_.features[q].data();
      double s = 0.0;
      for (std::size_t j = 0; j < active; ++j) s += phi[j] * y[j];
      moments_[q] = s;
    }
    for (const auto& [p, q, c] : couplings_) {
      const double* phi = form_.features[p].data();
      const double w = c * moments_[q];
      for (std::size_t k = 0; k < rows; ++k) rate[k] += w * phi[k];
    }
    return;
  }
  // cutoff: c_k = Σ_pq C_pq φ_p(k) P_q(N - k), P_q(m) = Σ_{j ≤ min(m, active)} φ_q(j) y_j
  for (std::size_t q = 0; q < rank(); ++q) {
    auto& prefix = partial_[q];
    prefix[0] = 0.0;
    for (std::size_t j = 1; j <= size_; ++j)
      prefix[j] = prefix[j - 1] + (j <= active ? form_.features[q][j - 1] * y[j - 1] : 0.0);
  }
  for (const auto& [p, q, c] : couplings_) {
    const double* phi = form_.features[p].data();
    const auto& prefix = partial_[q];
    for (std::size_t k = 1; k <= rows; ++k) rate[k - 1] += c * phi[k - 1] * prefix[size_ - k];
  }
}

double SeparableKernel::truncation_flux(std::span<const double> x, std::span<const double> y, std::size_t active) {
  const std::size_t N = size_;
  for (std::size_t q = 0; q < rank(); ++q) {  // suffix sums S_q(m) = Σ_{m ≤ j ≤ active} φ_q(j) y_j
    auto& suffix = partial_[q];
    suffix[N + 1] = 0.0;
    for (std::size_t j = N; j >= 1; --j)
      suffix[j] = suffix[j + 1] + (j <= active ? form_.features[q][j - 1] * y[j - 1] : 0.0);
  }
  double flux = 0.0;
  for (std::size_t i = 1; i <= active; ++i) {
    double rate = 0.0;
    for (const auto& [p, q, c] : couplings_) rate += c * form_.features[p][i - 1] * partial_[q][N - i + 1];
    flux += double(i) * x[i - 1] * rate;
  }
  return flux;
}

void SeparableKernel::transform(std::span<const double> x, std::size_t active, std::size_t length,
                                FftConvolution& fft, std::vector<FftConvolution::Spectrum>& spectra) {
  while (spectra.size() < rank()) spectra.push_back(fft.make_spectrum());
  for (std::size_t p = 0; p < rank(); ++p) {
    const double* phi = form_.features[p].data();
    for (std::size_t i = 0; i < active; ++i) work_[i] = phi[i] * x[i];
    fft.forward(work_.data(), active, length, spectra[p].data);
  }
}

void SeparableKernel::combine(const std::vector<FftConvolution::Spectrum>& a,
                              const std::vector<FftConvolution::Spectrum>& b, std::size_t m,
                              std::complex<double>* accumulator) const {
  std::fill(accumulator, accumulator + m, 0.0);
  for (const auto& [p, q, c] : couplings_) multiply_add(c, a[p].data, b[q].data, m, accumulator);
}

void SeparableKernel::combine_with(const std::vector<FftConvolution::Spectrum>& a, std::span<const double> y,
                                   std::size_t active, std::size_t length, FftConvolution& fft,
                                   std::complex<double>* accumulator) {
  if (!scratch_.data) scratch_ = fft.make_spectrum();
  const std::size_t m = fft.spectrum_size(length);
  std::fill(accumulator, accumulator + m, 0.0);
  for (std::size_t q = 0; q < rank(); ++q) {
    bool used = false;
    for (const auto& cp : couplings_) used |= cp.q == q;
    if (!used) continue;
    const double* phi = form_.features[q].data();
    for (std::size_t i = 0; i < active; ++i) work_[i] = phi[i] * y[i];
    fft.forward(work_.data(), active, length, scratch_.data);
    for (const auto& [p, qq, c] : couplings_)
      if (qq == q) multiply_add(c, a[p].data, scratch_.data, m, accumulator);
  }
}

double SeparableKernel::roundoff_bound(std::span<const double> x, std::size_t active) const {
  std::vector<double>& norms = norms_;  // reused: this runs on every right-hand side
  norms.resize(rank());
  for (std::size_t p = 0; p < rank(); ++p) {
    double s = 0.0;
    for (std::size_t i = 0; i < active; ++i) {
      const double y = form_.features[p][i] * x[i];
      s += y * y;
    }
    norms[p] = std::sqrt(s);
  }
  double bound = 0.0;
  for (const auto& [p, q, c] : couplings_) bound += std::abs(c) * norms[p] * norms[q];
  return bound;
}

}  // namespace aggkit

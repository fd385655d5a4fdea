#pragma once
// Operations with a separable kernel form K_ij = Σ_pq C_pq φ_p(i) φ_q(j) (solvers/kernels.hpp) that the
// fast right-hand side needs: collision rates c_k = Σ_j K_kj y_j in O(N·nnz(C)), spectra F(φ_p x) and
// their bilinear combinations Σ_pq C_pq F(φ_p x) F(φ_q y).
#include <complex>
#include <cstddef>
#include <span>
#include <vector>

#include "solvers/fft_convolution.hpp"
#include "solvers/kernels.hpp"

namespace aggkit {

class SeparableKernel {
 public:
  SeparableKernel(SeparableForm form, std::size_t N);

  const SeparableForm& form() const { return form_; }
  std::size_t rank() const { return form_.rank(); }
  double entry(std::size_t i, std::size_t j) const;  // K̃_ij, 1-based sizes

  // rate[k-1] = Σ_{j ≤ active} K̃_kj y_j for k ≤ rows (also j ≤ N - k when `cutoff`); rows = 0 means
  // rows = active.
  void collision_rates(std::span<const double> y, std::size_t active, bool cutoff, std::vector<double>& rate,
                       std::size_t rows = 0);
  // Σ_i i x_i Σ_{N-i < j ≤ active} K̃_ij y_j over i ≤ active: the mass flux out of the truncation.
  double truncation_flux(std::span<const double> x, std::span<const double> y, std::size_t active);

  // spectra[p] = F(φ_p x) over sizes 1..active, FFT length `length`.
  void transform(std::span<const double> x, std::size_t active, std::size_t length, FftConvolution& fft,
                 std::vector<FftConvolution::Spectrum>& spectra);
  // accumulator = Σ_pq C_pq a_p b_q over the first m frequencies.
  void combine(const std::vector<FftConvolution::Spectrum>& a, const std::vector<FftConvolution::Spectrum>& b,
               std::size_t m, std::complex<double>* accumulator) const;
  // accumulator = Σ_pq C_pq a_p F(φ_q y): transforms y feature by feature (one scratch spectrum).
  void combine_with(const std::vector<FftConvolution::Spectrum>& a, std::span<const double> y, std::size_t active,
                    std::size_t length, FftConvolution& fft, std::complex<double>* accumulator);
  // Σ_pq |C_pq| ||φ_p x|| ||φ_q x||: the FFT round-off bound of the self-convolution, up to ε log L.
  double roundoff_bound(std::span<const double> x, std::size_t active) const;

 private:
  struct Coupling {
    std::size_t p, q;
    double c;
  };
  SeparableForm form_;
  std::size_t size_;
  std::vector<Coupling> couplings_;
  std::vector<double> work_, moments_;
  mutable std::vector<double> norms_;
  std::vector<std::vector<double>> partial_;
  FftConvolution::Spectrum scratch_;
};

}  // namespace aggkit

#pragma once
// Linear convolutions of sequences supported on sizes 1..K through real FFTs (FFTW), with cached plans
// for lengths 2^m and 3·2^m so that the active size range can change between calls.
#include <complex>
#include <cstddef>
#include <map>
#include <memory>
#include <vector>

namespace aggkit {

class FftConvolution {
 public:
  explicit FftConvolution(std::size_t max_support);
  ~FftConvolution();
  FftConvolution(const FftConvolution&) = delete;
  FftConvolution& operator=(const FftConvolution&) = delete;

  // FFT length used for inputs supported on sizes 1..support: no wrap-around for sums ≤ 2·support.
  std::size_t length_for(std::size_t support) const;
  std::size_t spectrum_size(std::size_t length) const { return length / 2 + 1; }

  // Forward transform of values[0..support) (values[i] belongs to size i+1), zero-padded to `length`.
  void forward(const double* values, std::size_t support, std::size_t length, std::complex<double>* spectrum);
  // Inverse transform of `spectrum` (destroyed); writes sums s = 2..last into out[s - 2], scaled by 1/length.
  void inverse(std::complex<double>* spectrum, std::size_t length, std::size_t last, double* out);

  // Buffer for one spectrum of the largest length (aligned for FFTW).
  struct Spectrum {
    std::complex<double>* data = nullptr;
    Spectrum() = default;
    explicit Spectrum(std::size_t n);
    Spectrum(Spectrum&& o) noexcept : data(o.data) { o.data = nullptr; }
    Spectrum& operator=(Spectrum&& o) noexcept;
    ~Spectrum();
  };
  Spectrum make_spectrum() const { return Spectrum(spectrum_size(max_length_)); }

 private:
  struct Plans;
  Plans& plans(std::size_t length);
  std::size_t max_length_;
  double* real_ = nullptr;  // scratch of max_length_ doubles
  std::map<std::size_t, std::unique_ptr<Plans>> plans_;
};

}  // namespace aggkit

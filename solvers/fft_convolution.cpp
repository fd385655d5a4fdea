#include "solvers/fft_convolution.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cstring>
#include <mutex>
#include <new>

namespace aggkit {

namespace {
std::mutex planner_mutex;  // the FFTW planner is not thread-safe; execution is

std::size_t smooth_length(std::size_t minimum) {
  std::size_t power = 64;
  while (power < minimum) power *= 2;
  const std::size_t three = 3 * (power / 4);  // 3·2^m between power/2 and power
  return three >= minimum ? three : power;
}
}  // namespace

struct FftConvolution::Plans {
  fftw_plan forward = nullptr, inverse = nullptr;
  ~Plans() {
    std::lock_guard lock(planner_mutex);
    if (forward) fftw_destroy_plan(forward);
    if (inverse) fftw_destroy_plan(inverse);
  }
};

FftConvolution::Spectrum::Spectrum(std::size_t n)
    : data(reinterpret_cast<std::complex<double>*>(fftw_malloc(sizeof(fftw_complex) * n))) {
  if (!data) throw std::bad_alloc();
  std::fill(data, data + n, std::complex<double>(0.0));
}
FftConvolution::Spectrum& FftConvolution::Spectrum::operator=(Spectrum&& o) noexcept {
  std::swap(data, o.data);
  return *this;
}
FftConvolution::Spectrum::~Spectrum() {
  if (data) fftw_free(data);
}

FftConvolution::FftConvolution(std::size_t max_support) : max_length_(smooth_length(2 * max_support)) {
  real_ = static_cast<double*>(fftw_malloc(sizeof(double) * max_length_));
  if (!real_) throw std::bad_alloc();
}

FftConvolution::~FftConvolution() {
  plans_.clear();
  fftw_free(real_);
}

std::size_t FftConvolution::length_for(std::size_t support) const {
  return std::min(max_length_, smooth_length(2 * support));
}

FftConvolution::Plans& FftConvolution::plans(std::size_t length) {
  auto it = plans_.find(length);
  if (it != plans_.end()) return *it->second;
  auto p = std::make_unique<Plans>();
  Spectrum scratch(spectrum_size(length));
  auto* c = reinterpret_cast<fftw_complex*>(scratch.data);
  {
    std::lock_guard lock(planner_mutex);
    p->forward = fftw_plan_dft_r2c_1d(int(length), real_, c, FFTW_ESTIMATE);
    p->inverse = fftw_plan_dft_c2r_1d(int(length), c, real_, FFTW_ESTIMATE | FFTW_DESTROY_INPUT);
  }
  return *plans_.emplace(length, std::move(p)).first->second;
}

void FftConvolution::forward(const double* values, std::size_t support, std::size_t length,
                             std::complex<double>* spectrum) {
  std::memcpy(real_, values, sizeof(double) * support);
  std::fill(real_ + support, real_ + length, 0.0);
  fftw_execute_dft_r2c(plans(length).forward, real_, reinterpret_cast<fftw_complex*>(spectrum));
}

void FftConvolution::inverse(std::complex<double>* spectrum, std::size_t length, std::size_t last, double* out) {
  fftw_execute_dft_c2r(plans(length).inverse, reinterpret_cast<fftw_complex*>(spectrum), real_);
  // Position p holds the sum of index pairs (i-1) + (j-1) = p, i.e. sizes i + j = p + 2.
  const double scale = 1.0 / double(length);
  for (std::size_t s = 2; s <= last; ++s) out[s - 2] = s - 2 < length ? real_[s - 2] * scale : 0.0;
}

}  // namespace aggkit

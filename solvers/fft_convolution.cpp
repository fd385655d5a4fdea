#include "solvers/fft_convolution.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <new>
#include <string>
#include <unistd.h>

namespace aggkit {

namespace {
std::mutex planner_mutex;  // the FFTW planner is not thread-safe; execution is

// Planning. FFTW_MEASURE plans run about twice as fast as FFTW_ESTIMATE ones for lengths 3·2^m and
// 10-25 % faster for 2^m (bench/results/log/cvode-work-precision.md), but take ~0.1-1 s each to make. AGGKIT_FFT_PLANNING picks:
//   adaptive (default): a length is first planned with FFTW_ESTIMATE, or measured at once if FFTW's
//     wisdom already knows it; after `measure_after` executions (about the break-even point) it is
//     re-planned with FFTW_MEASURE, so short runs never pay for planning and long runs pay once;
//   measure: FFTW_MEASURE at once;  estimate: never measure (no wisdom file is read or written).
// Measured plans are remembered as FFTW "wisdom" in a file shared by all runs: $AGGKIT_FFTW_WISDOM,
// else ~/.cache/aggkit/fftw-wisdom (written atomically; unwritable means not remembered).
struct Planning {
  enum Mode { adaptive, measure, estimate } mode = adaptive;
  static constexpr long measure_after = 50000;
  std::string wisdom_file;
  Planning() {
    if (const char* m = std::getenv("AGGKIT_FFT_PLANNING")) {
      const std::string name(m);
      mode = name == "measure" ? measure : name == "estimate" ? estimate : adaptive;
    }
    if (mode == estimate) return;
    if (const char* file = std::getenv("AGGKIT_FFTW_WISDOM")) wisdom_file = file;
    else if (const char* home = std::getenv("HOME")) wisdom_file = std::string(home) + "/.cache/aggkit/fftw-wisdom";
    if (!wisdom_file.empty()) fftw_import_wisdom_from_filename(wisdom_file.c_str());  // absent: nothing learnt yet
  }
  void save() const {
    if (wisdom_file.empty()) return;
    std::error_code ignored;
    std::filesystem::create_directories(std::filesystem::path(wisdom_file).parent_path(), ignored);
    const std::string partial = wisdom_file + ".partial." + std::to_string(::getpid());
    if (fftw_export_wisdom_to_filename(partial.c_str())) std::rename(partial.c_str(), wisdom_file.c_str());
    else std::remove(partial.c_str());
  }
};
Planning& planning() {
  static Planning p;  // thread-safe initialisation
  return p;
}

// Smallest planned length ≥ minimum of the form 2^m or 3·2^m (m ≥ 5).
std::size_t smooth_length(std::size_t minimum) {
  std::size_t power = 64;
  while (power < minimum) power *= 2;
  const std::size_t three = 3 * (power / 4);  // 3·2^m between power/2 and power
  return three >= minimum ? three : power;
}
}  // namespace

struct FftConvolution::Plans {
  fftw_plan forward = nullptr, inverse = nullptr;
  bool measured = false;
  long executions = 0;
  void destroy() {
    if (forward) fftw_destroy_plan(forward);
    if (inverse) fftw_destroy_plan(inverse);
    forward = inverse = nullptr;
  }
  ~Plans() {
    std::lock_guard lock(planner_mutex);
    destroy();
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
  if (it == plans_.end()) it = plans_.emplace(length, std::make_unique<Plans>()).first;
  Plans& p = *it->second;
  const bool fresh = !p.forward;
  const bool due = !p.measured && planning().mode == Planning::adaptive && ++p.executions == Planning::measure_after;
  if (!fresh && !due) return p;
  // Planning with FFTW_MEASURE overwrites the arrays it is given: scratch spectrum and real_ (callers
  // plan before filling real_).
  Spectrum scratch(spectrum_size(length));
  auto* c = reinterpret_cast<fftw_complex*>(scratch.data);
  const int n = int(length);
  std::lock_guard lock(planner_mutex);
  Planning& how = planning();
  if (fresh && how.mode != Planning::estimate) {  // measured plans straight from wisdom, if it has them
    p.forward = fftw_plan_dft_r2c_1d(n, real_, c, FFTW_MEASURE | FFTW_WISDOM_ONLY);
    p.inverse = fftw_plan_dft_c2r_1d(n, c, real_, FFTW_MEASURE | FFTW_WISDOM_ONLY | FFTW_DESTROY_INPUT);
    p.measured = p.forward && p.inverse;
    if (p.measured) return p;
    p.destroy();
  }
  const bool measure = due || how.mode == Planning::measure;
  p.destroy();
  const unsigned flags = measure ? FFTW_MEASURE : FFTW_ESTIMATE;
  p.forward = fftw_plan_dft_r2c_1d(n, real_, c, flags);
  p.inverse = fftw_plan_dft_c2r_1d(n, c, real_, flags | FFTW_DESTROY_INPUT);
  p.measured = measure;
  if (measure) how.save();
  return p;
}

void FftConvolution::forward(const double* values, std::size_t support, std::size_t length,
                             std::complex<double>* spectrum) {
  const Plans& plan = plans(length);  // before filling real_ (planning may use it)
  std::memcpy(real_, values, sizeof(double) * support);
  std::fill(real_ + support, real_ + length, 0.0);
  fftw_execute_dft_r2c(plan.forward, real_, reinterpret_cast<fftw_complex*>(spectrum));
}

void FftConvolution::inverse(std::complex<double>* spectrum, std::size_t length, std::size_t last, double* out) {
  const Plans& plan = plans(length);  // planning does not touch `spectrum`
  fftw_execute_dft_c2r(plan.inverse, reinterpret_cast<fftw_complex*>(spectrum), real_);
  // Position p holds the sum of index pairs (i-1) + (j-1) = p, i.e. sizes i + j = p + 2.
  const double scale = 1.0 / double(length);
  for (std::size_t s = 2; s <= last; ++s) out[s - 2] = s - 2 < length ? real_[s - 2] * scale : 0.0;
}

}  // namespace aggkit

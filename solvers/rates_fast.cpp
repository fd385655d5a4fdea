// Fast evaluation of the aggregation-shattering right-hand side, O(N R log N) per call, from a
// separable kernel form K_ij = Σ_pq C_pq φ_p(i) φ_q(j) (DESIGN.md "Deterministic numerics"):
//   gain_k = ½ Σ_{i+j=k} K_ij n_i n_j = ½ IFFT[ Σ_pq C_pq F(φ_p n) F(φ_q n) ]_k,
//   collision rate c_k = Σ_j K_kj n_j = Σ_pq C_pq φ_p(k) Σ_j φ_q(j) n_j (prefix sums for `cutoff`),
//   monomer source λ n_1 Σ_{j≥2} j K_1j n_j + (λ/2) Σ_{i,j≥2} (i+j) K_ij n_i n_j = λ Σ_{i≥2} i n_i c_i
// (the terms with one monomer cancel between the two sums; symmetry of K turns the double sum into
// a single one).
//
// Far-tail round-off. An FFT convolution errs by about ε log2(L) ||x|| ||y|| in every entry, so sizes
// whose true gain is far below the largest one would receive noise of either sign (and the solver,
// asked for tight tolerances, would chase that noise). The gain is therefore also convolved in an
// exponentially tilted form: with x̃_k = x_k e^{θ(k-k0)}, (x̃ * ỹ)_s = e^{θ(s-2k0)} (x * y)_s, so the
// round-off of the tilted convolution, mapped back, decays like e^{-θ s} together with the
// distribution. θ is the slowest decay rate of n beyond its peak k0, θ = min_k ln(G n_k0/|n_k|)/(k-k0)
// with G = 10 (so |x̃| ≤ G max|n|, no overflow). Each size takes its gain from whichever of the plain
// and the tilted convolution has the smaller round-off bound ε Σ|C_pq| ||φ_p x|| ||φ_q x|| (times
// e^{-θ(s-2k0)} for the tilted one): the plain one near the peak, the tilted one in the tail. Sizes
// with n_k ≤ 1e-300 max n take no part in collisions (the active range 1..K_a), which also shortens
// the FFTs at early times. The Jacobian-vector product uses the plain convolution (a Krylov vector
// need not decay); it only steers Newton's method.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "solvers/fft_convolution.hpp"
#include "solvers/rates.hpp"

namespace aggkit {

namespace {

struct Coupling {
  std::size_t p, q;
  double c;
};

class FastRates final : public Rates {
 public:
  FastRates(const AggregationModel& model, double lowrank_tolerance)
      : Rates(model.size),
        model_(model),
        cutoff_(model.truncation == Truncation::cutoff),
        form_(model.kernel.separable_form(model.size, lowrank_tolerance)),
        rank_(form_.rank()),
        fft_(model.size) {
    for (std::size_t p = 0; p < rank_; ++p)
      for (std::size_t q = 0; q < rank_; ++q)
        if (form_.coupling[p][q] != 0.0) couplings_.push_back({p, q, form_.coupling[p][q]});
    for (std::size_t p = 0; p < rank_; ++p) {
      spectra_n_.push_back(fft_.make_spectrum());
      tilted_.push_back(fft_.make_spectrum());
    }
    spectrum_v_ = fft_.make_spectrum();
    accumulator_ = fft_.make_spectrum();
    kernel_diagonal_.resize(size_);
    kernel_monomer_.resize(size_);
    for (std::size_t k = 1; k <= size_; ++k) {
      kernel_diagonal_[k - 1] = entry(k, k);
      kernel_monomer_[k - 1] = entry(k, 1);
    }
    cached_n_.assign(size_, std::nan(""));
    rate_n_.resize(size_);
    rate_v_.resize(size_);
    work_.resize(size_);
    tilted_n_.resize(size_);
    plain_n_.resize(size_);
    tilted_conv_.resize(2 * size_);
    conv_.resize(2 * size_);
    partial_.assign(rank_, std::vector<double>(size_ + 2, 0.0));
  }

  void evaluate(double t, std::span<const double> n, std::span<double> dndt) override {
    prepare(n);
    const double lambda = model_.lambda(t);
    // gain: ½ Σ_pq C_pq F_p F_q, inverse transformed, plain and tilted.
    const std::size_t last = std::min(size_, 2 * active_);
    std::fill(dndt.begin(), dndt.end(), 0.0);
    if (last >= 2) {
      self_convolution(spectra_n_, conv_);
      if (tilt_ > 0.0) self_convolution(tilted_, tilted_conv_);
      for (std::size_t k = 2; k <= last; ++k) {
        const double untilt = std::exp(-tilt_ * (double(k) - 2.0 * double(peak_)));
        const bool use_tilted = tilt_ > 0.0 && tilted_bound_ * untilt < plain_bound_;
        dndt[k - 1] = 0.5 * (use_tilted ? tilted_conv_[k - 2] * untilt : conv_[k - 2]);
      }
    }
    double shattered = 0.0;
    for (std::size_t k = 1; k <= active_; ++k) {
      const double loss = n[k - 1] * rate_n_[k - 1];
      dndt[k - 1] -= (k == 1 ? 1.0 : 1.0 + lambda) * loss;
      if (k >= 2) shattered += double(k) * loss;
    }
    dndt[0] += lambda * shattered;
  }

  void jacobian_times(double t, std::span<const double> n, std::span<const double> v,
                      std::span<double> Jv) override {
    prepare(n);
    const double lambda = model_.lambda(t);
    std::fill(Jv.begin(), Jv.end(), 0.0);
    const std::size_t last = std::min(size_, 2 * active_);
    // Cross convolution Σ_{i+j=k} K_ij n_i v_j = IFFT[Σ_pq C_pq F(φ_p n) F(φ_q v)] (v restricted to
    // the active range, as n is: this is the exact derivative of evaluate()).
    if (last >= 2) {
      const std::size_t m = fft_.spectrum_size(length_);
      std::fill(accumulator_.data, accumulator_.data + m, 0.0);
      for (std::size_t q = 0; q < rank_; ++q) {
        bool used = false;
        for (const auto& cp : couplings_) used |= cp.q == q;
        if (!used) continue;
        const double* phi = form_.features[q].data();
        for (std::size_t i = 0; i < active_; ++i) work_[i] = phi[i] * v[i];
        fft_.forward(work_.data(), active_, length_, spectrum_v_.data);
        for (const auto& [p, qq, c] : couplings_)
          if (qq == q)
            for (std::size_t f = 0; f < m; ++f) accumulator_.data[f] += c * spectra_n_[p].data[f] * spectrum_v_.data[f];
      }
      fft_.inverse(accumulator_.data, length_, last, conv_.data());
      for (std::size_t k = 2; k <= last; ++k) Jv[k - 1] = conv_[k - 2];
    }
    collision_rates(v, rate_v_);
    double shattered = 0.0;
    for (std::size_t k = 1; k <= active_; ++k) {
      const double loss = v[k - 1] * rate_n_[k - 1] + n[k - 1] * rate_v_[k - 1];
      Jv[k - 1] -= (k == 1 ? 1.0 : 1.0 + lambda) * loss;
      if (k >= 2) shattered += double(k) * loss;
    }
    Jv[0] += lambda * shattered;
  }

  void jacobian_diagonal(double t, std::span<const double> n, std::span<double> diagonal) override {
    prepare(n);
    const double lambda = model_.lambda(t);
    std::fill(diagonal.begin(), diagonal.end(), 0.0);
    double monomer = 0.0;  // ∂/∂n_1 of λ Σ_{i≥2} i n_i c_i = λ Σ_{i≥2} i n_i K_i1
    for (std::size_t k = 1; k <= active_; ++k) {
      const bool self_pair = !cutoff_ || 2 * k <= size_;
      diagonal[k - 1] = -(k == 1 ? 1.0 : 1.0 + lambda) *
                        (rate_n_[k - 1] + (self_pair ? n[k - 1] * kernel_diagonal_[k - 1] : 0.0));
      if (k >= 2 && (!cutoff_ || k + 1 <= size_)) monomer += double(k) * n[k - 1] * kernel_monomer_[k - 1];
    }
    diagonal[0] += lambda * monomer;
  }

  double leak_rate(double, std::span<const double> n) override {
    if (cutoff_) return 0.0;
    prepare(n);
    // ½ Σ_{i+j>N} (i+j) K_ij n_i n_j = Σ_i i n_i Σ_{j>N-i} K_ij n_j, from suffix sums of φ_q n over
    // the active range (the same truncated n that evaluate() uses, so leak = -dM1/dt exactly).
    const std::size_t N = size_, A = active_;
    for (std::size_t q = 0; q < rank_; ++q) {
      auto& suffix = partial_[q];
      suffix[N + 1] = 0.0;
      for (std::size_t j = N; j >= 1; --j)
        suffix[j] = suffix[j + 1] + (j <= A ? form_.features[q][j - 1] * n[j - 1] : 0.0);
    }
    double leak = 0.0;
    for (std::size_t i = 1; i <= A; ++i) {
      double rate = 0.0;
      for (const auto& [p, q, c] : couplings_) rate += c * form_.features[p][i - 1] * partial_[q][N - i + 1];
      leak += double(i) * n[i - 1] * rate;
    }
    return leak;
  }

  std::string describe() const override {
    return "fft, separable rank " + std::to_string(rank_) + (form_.exact ? " (exact)" : " (approximate)");
  }
  std::size_t kernel_rank() const override { return rank_; }
  double kernel_relative_error() const override { return form_.max_relative_error; }

 private:
  double entry(std::size_t i, std::size_t j) const {
    double sum = 0.0;
    for (const auto& [p, q, c] : couplings_) sum += c * form_.features[p][i - 1] * form_.features[q][j - 1];
    return sum;
  }

  // out[s-2] = Σ_pq C_pq IFFT(S_p S_q)_s for s = 2..min(N, 2 K_a).
  void self_convolution(const std::vector<FftConvolution::Spectrum>& spectra, std::vector<double>& out) {
    const std::size_t m = fft_.spectrum_size(length_);
    std::fill(accumulator_.data, accumulator_.data + m, 0.0);
    for (const auto& [p, q, c] : couplings_)
      for (std::size_t f = 0; f < m; ++f) accumulator_.data[f] += c * spectra[p].data[f] * spectra[q].data[f];
    fft_.inverse(accumulator_.data, length_, std::min(size_, 2 * active_), out.data());
  }

  // Round-off bound (up to the common factor ε log L) of Σ_pq C_pq (φ_p x * φ_q x).
  double roundoff_bound(const std::vector<double>& x) const {
    std::vector<double> norms(rank_);
    for (std::size_t p = 0; p < rank_; ++p) {
      double s = 0.0;
      for (std::size_t i = 0; i < active_; ++i) s += std::pow(form_.features[p][i] * x[i], 2);
      norms[p] = std::sqrt(s);
    }
    double bound = 0.0;
    for (const auto& [p, q, c] : couplings_) bound += std::abs(c) * norms[p] * norms[q];
    return bound;
  }

  // c_k = Σ_{j ≤ K_a} K_kj y_j (j ≤ N - k as well for cutoff), for k ≤ K_a.
  void collision_rates(std::span<const double> y, std::vector<double>& rate) {
    const std::size_t A = active_;
    std::fill(rate.begin(), rate.end(), 0.0);
    if (!cutoff_) {
      std::vector<double>& moments = moments_;
      moments.assign(rank_, 0.0);
      for (std::size_t q = 0; q < rank_; ++q) {
        const double* phi = form_.features[q].data();
        double s = 0.0;
        for (std::size_t j = 0; j < A; ++j) s += phi[j] * y[j];
        moments[q] = s;
      }
      for (const auto& [p, q, c] : couplings_) {
        const double* phi = form_.features[p].data();
        const double w = c * moments[q];
        for (std::size_t k = 0; k < A; ++k) rate[k] += w * phi[k];
      }
      return;
    }
    for (std::size_t q = 0; q < rank_; ++q) {  // prefix[m] = Σ_{j ≤ min(m, K_a)} φ_q(j) y_j
      auto& prefix = partial_[q];
      prefix[0] = 0.0;
      for (std::size_t j = 1; j <= size_; ++j)
        prefix[j] = prefix[j - 1] + (j <= A ? form_.features[q][j - 1] * y[j - 1] : 0.0);
    }
    for (const auto& [p, q, c] : couplings_) {
      const double* phi = form_.features[p].data();
      const auto& prefix = partial_[q];
      for (std::size_t k = 1; k <= A; ++k) rate[k - 1] += c * phi[k - 1] * prefix[size_ - k];
    }
  }

  // Caches, for the state n: the active range, the tilt, the plain and tilted spectra F(φ_p n),
  // F(φ_p n e^{θ(k-k0)}), their round-off bounds, and the collision rates c(n).
  void prepare(std::span<const double> n) {
    if (std::memcmp(n.data(), cached_n_.data(), sizeof(double) * size_) == 0) return;
    std::copy(n.begin(), n.end(), cached_n_.begin());
    peak_ = 1;
    for (std::size_t k = 1; k <= size_; ++k)
      if (std::abs(n[k - 1]) > std::abs(n[peak_ - 1])) peak_ = k;
    const double largest = std::abs(n[peak_ - 1]);
    active_ = 1;
    for (std::size_t k = size_; k >= 1; --k)
      if (std::abs(n[k - 1]) > 1e-300 * largest) {
        active_ = k;
        break;
      }
    length_ = fft_.length_for(active_);
    // Tilt: slowest decay rate beyond the peak, with growth allowance G = 10.
    tilt_ = INFINITY;
    const double log_reference = std::log(10.0 * largest);
    for (std::size_t k = peak_ + 1; k <= active_; ++k)
      if (n[k - 1] != 0.0) tilt_ = std::min(tilt_, (log_reference - std::log(std::abs(n[k - 1]))) / double(k - peak_));
    if (!std::isfinite(tilt_) || largest == 0.0) tilt_ = 0.0;
    std::copy(n.begin(), n.begin() + active_, plain_n_.begin());
    transform(plain_n_, spectra_n_);
    plain_bound_ = roundoff_bound(plain_n_);
    if (tilt_ > 0.0) {
      for (std::size_t k = 1; k <= active_; ++k) {
        const double x = n[k - 1];
        tilted_n_[k - 1] =
            x == 0.0 ? 0.0 : std::copysign(std::exp(std::log(std::abs(x)) + tilt_ * (double(k) - double(peak_))), x);
      }
      transform(tilted_n_, tilted_);
      tilted_bound_ = roundoff_bound(tilted_n_);
    }
    collision_rates(n, rate_n_);
  }

  void transform(const std::vector<double>& x, std::vector<FftConvolution::Spectrum>& spectra) {
    for (std::size_t p = 0; p < rank_; ++p) {
      const double* phi = form_.features[p].data();
      for (std::size_t i = 0; i < active_; ++i) work_[i] = phi[i] * x[i];
      fft_.forward(work_.data(), active_, length_, spectra[p].data);
    }
  }

  const AggregationModel& model_;
  bool cutoff_;
  SeparableForm form_;
  std::size_t rank_;
  std::vector<Coupling> couplings_;
  FftConvolution fft_;
  std::vector<FftConvolution::Spectrum> spectra_n_, tilted_;
  FftConvolution::Spectrum spectrum_v_, accumulator_;
  std::vector<double> kernel_diagonal_, kernel_monomer_;
  std::vector<double> cached_n_, rate_n_, rate_v_, work_, conv_, moments_;
  std::vector<std::vector<double>> partial_;
  std::vector<double> plain_n_, tilted_n_, tilted_conv_;
  double tilt_ = 0.0, plain_bound_ = 0.0, tilted_bound_ = 0.0;
  std::size_t active_ = 1, length_ = 0, peak_ = 1;
};

}  // namespace

std::unique_ptr<Rates> make_fast_rates(const AggregationModel& model, double lowrank_tolerance) {
  return std::make_unique<FastRates>(model, lowrank_tolerance);
}

}  // namespace aggkit

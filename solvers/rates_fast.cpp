// Fast evaluation of the aggregation-shattering right-hand side, O(N R log N) per call, from a
// separable kernel form K_ij = Σ_pq C_pq φ_p(i) φ_q(j) (solvers/kernels.hpp), for the equations of
// solvers/model.hpp:
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
// with n_k ≤ 1e-300 max n take no part in collisions. The Jacobian-vector product uses the plain
// convolution (a Krylov vector need not decay); it only steers Newton's method.
//
// Active size range. Sizes 1..K_a take part in collisions; K_a is the last size with |n_k| above its
// negligible level ν_k (set by the integrator to a small fraction of the absolute tolerance atol_k; without
// levels, 1e-300 max n). Every transform, product and sum then covers 1..K_a, and the FFT length is the
// smallest planned one ≥ 2 K_a. The truncated system is the full one with the pairs that involve a size
// beyond K_a left out: pairs inside the range gain into sizes up to 2 K_a (so the tail beyond K_a keeps
// growing from the resolved sizes), lose, and shatter exactly as in the full system, so mass is conserved
// term by term. What is left out is of order ν: a size k > K_a (|n_k| ≤ ν_k) misses its own loss (at most
// ν_k), and a size i ≤ K_a misses the collisions with it, a relative rate Σ_{k>K_a} K_ik ν_k. As soon as a
// size beyond the edge, fed by the gain, rises above ν_k it joins, so the range grows before its tail
// reaches the tolerance; sizes beyond 2 K_a stay exactly 0. At early times, when the distribution covers a
// few hundred of N sizes, the FFTs shrink accordingly.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "solvers/fft_convolution.hpp"
#include "solvers/rates.hpp"
#include "solvers/separable_kernel.hpp"

namespace aggkit {

namespace {

class FastRates final : public Rates {
 public:
  FastRates(const AggregationModel& model, double lowrank_tolerance, double jacobian_tolerance)
      : Rates(model.size),
        model_(model),
        cutoff_(model.truncation == Truncation::cutoff),
        kernel_(model.kernel.separable_form(model.size, lowrank_tolerance), model.size),
        fft_(model.size) {
    if (!kernel_.form().exact && jacobian_tolerance > lowrank_tolerance)
      newton_kernel_ = std::make_unique<SeparableKernel>(model.kernel.separable_form(size_, jacobian_tolerance), size_);
    kernel_diagonal_.resize(size_);
    kernel_monomer_.resize(size_);
    kernel_subdiagonal_.resize(size_);
    for (std::size_t k = 1; k <= size_; ++k) {
      kernel_diagonal_[k - 1] = kernel_.entry(k, k);
      kernel_monomer_[k - 1] = kernel_.entry(k, 1);
      kernel_subdiagonal_[k - 1] = k >= 2 ? kernel_.entry(k, k - 1) : 0.0;
    }
    accumulator_ = fft_.make_spectrum();
    cached_n_.assign(size_, std::nan(""));
    for (auto* v : {&rate_n_, &rate_v_, &tilted_n_}) v->resize(size_);
    for (auto* v : {&conv_, &tilted_conv_}) v->resize(2 * size_);
  }

  void evaluate(double t, std::span<const double> n, std::span<double> dndt) override {
    prepare(n);
    const double lambda = model_.lambda(t);
    std::fill(dndt.begin(), dndt.end(), 0.0);
    // Gain ½ Σ_{i+j=k} K_ij n_i n_j = ½ IFFT[Σ_pq C_pq F(φ_p n) F(φ_q n)], plain and/or tilted.
    const std::size_t last = std::min(size_, 2 * active_);
    if (last >= 2) {
      const std::size_t m = fft_.spectrum_size(length_);
      if (use_plain_) {  // sums s ≤ 2·plain_support_ only
        kernel_.combine(plain_, plain_, fft_.spectrum_size(plain_length_), accumulator_.data);
        fft_.inverse(accumulator_.data, plain_length_, std::min(last, plain_valid_), conv_.data());
      }
      if (use_tilted_) {
        kernel_.combine(tilted_, tilted_, m, accumulator_.data);
        fft_.inverse(accumulator_.data, length_, last, tilted_conv_.data());
      }
      // e^{-θ(k-2k0)} by recurrence (relative round-off k ε, below the FFT's own).
      const double step = std::exp(-tilt_);
      double untilt = std::exp(-tilt_ * (2.0 - 2.0 * double(peak_)));
      for (std::size_t k = 2; k <= last; ++k, untilt *= step) {
        const bool tilted = use_tilted_ && (!use_plain_ || k > plain_valid_ || tilted_bound_ * untilt < plain_bound_);
        dndt[k - 1] = 0.5 * (tilted ? tilted_conv_[k - 2] * untilt : conv_[k - 2]);
      }
    }
    // Loss -(1+λ) n_k c_k (k ≥ 2), -n_1 c_1; monomers from shattering λ Σ_{i≥2} i n_i c_i.
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
    SeparableKernel& kernel = newton_kernel_ ? *newton_kernel_ : kernel_;
    const double lambda = model_.lambda(t);
    std::fill(Jv.begin(), Jv.end(), 0.0);
    // Cross convolution Σ_{i+j=k} K_ij n_i v_j (v restricted to the active range, as n is).
    const std::size_t last = std::min(size_, 2 * active_);
    if (last >= 2) {
      if (!newton_spectra_ready_) {  // F(φ_p n) at full length, once per state
        kernel.transform(n, active_, length_, fft_, newton_plain_);
        newton_spectra_ready_ = true;
      }
      kernel.combine_with(newton_plain_, v, active_, length_, fft_, accumulator_.data);
      fft_.inverse(accumulator_.data, length_, last, conv_.data());
      for (std::size_t k = 2; k <= last; ++k) Jv[k - 1] = conv_[k - 2];
    }
    kernel.collision_rates(v, active_, cutoff_, rate_v_);
    double shattered = 0.0;
    for (std::size_t k = 1; k <= active_; ++k) {
      const double loss = v[k - 1] * rate_n_[k - 1] + n[k - 1] * rate_v_[k - 1];
      Jv[k - 1] -= (k == 1 ? 1.0 : 1.0 + lambda) * loss;
      if (k >= 2) shattered += double(k) * loss;
    }
    Jv[0] += lambda * shattered;
    // Sizes beyond the active range (n_k ≈ 0) keep the loss -(1+λ) c_k v_k of their own perturbation,
    // so that J has no spurious zero rows (eigenvalues 0) there.
    for (std::size_t k = active_ + 1; k <= size_; ++k) Jv[k - 1] -= (1.0 + lambda) * rate_n_[k - 1] * v[k - 1];
  }

  void jacobian_monomer_coupling(double t, std::span<const double> n, MonomerCoupling& J) override {
    prepare(n);
    const double lambda = model_.lambda(t);
    for (auto* v : {&J.diagonal, &J.subdiagonal, &J.monomer_column}) v->assign(size_, 0.0);
    auto allowed = [&](std::size_t i, std::size_t j) { return !cutoff_ || i + j <= size_; };
    double monomer = 0.0;  // ∂/∂n_1 of λ Σ_{i≥2} i n_i c_i = λ Σ_{i≥2} i n_i K_i1
    for (std::size_t k = 1; k <= active_; ++k) {
      const double loss_factor = k == 1 ? 1.0 : 1.0 + lambda;
      J.diagonal[k - 1] = -loss_factor * (rate_n_[k - 1] + (allowed(k, k) ? n[k - 1] * kernel_diagonal_[k - 1] : 0.0));
      if (k >= 2 && allowed(k, 1)) monomer += double(k) * n[k - 1] * kernel_monomer_[k - 1];
      if (k >= 2)  // ∂f_k/∂n_1 = K_{1,k-1} n_{k-1} - (1+λ) n_k K_k1
        J.monomer_column[k - 1] = kernel_monomer_[k - 2] * n[k - 2] - (allowed(k, 1) ? loss_factor * n[k - 1] * kernel_monomer_[k - 1] : 0.0);
      if (k >= 3)  // ∂f_k/∂n_{k-1} = K_{k-1,1} n_1 - (1+λ) n_k K_{k,k-1}
        J.subdiagonal[k - 1] = kernel_monomer_[k - 2] * n[0] -
                               (allowed(k, k - 1) ? loss_factor * n[k - 1] * kernel_subdiagonal_[k - 1] : 0.0);
    }
    J.diagonal[0] += lambda * monomer;
    for (std::size_t k = active_ + 1; k <= size_; ++k) J.diagonal[k - 1] = -(1.0 + lambda) * rate_n_[k - 1];
  }

  double leak_rate(double, std::span<const double> n) override {
    if (cutoff_) return 0.0;
    if (std::memcmp(n.data(), cached_n_.data(), sizeof(double) * size_) != 0) {
      find_active_range(n);  // the cache is stale: refresh only the range (no FFT) and mark it stale
      cached_n_[0] = std::nan("");
    }
    // ½ Σ_{i+j>N} (i+j) K_ij n_i n_j = Σ_i i n_i Σ_{j>N-i} K_ij n_j over the active range (the same
    // truncated n that evaluate() uses, so leak = -dM1/dt exactly); no pair leaves while 2 K_a ≤ N.
    if (2 * active_ <= size_) return 0.0;
    return kernel_.truncation_flux(n, n, active_);
  }

  std::string describe() const override {
    return "fft, separable rank " + std::to_string(kernel_.rank()) + (kernel_.form().exact ? " (exact)" : " (approximate)");
  }
  std::size_t kernel_rank() const override { return kernel_.rank(); }
  double kernel_relative_error() const override { return kernel_.form().max_relative_error; }

  void set_negligible_levels(std::vector<double> levels) override {
    negligible_ = std::move(levels);
    negligible_.resize(negligible_.empty() ? 0 : size_, 0.0);
    cached_n_[0] = std::nan("");  // the active range may change for the same state
  }
  ActiveRangeStatistics active_range_statistics() const override {
    if (states_ == 0) return {size_, double(size_), 1.0, 0};
    const double full = work(fft_.length_for(size_));
    return {active_, double(active_sum_) / double(states_), fft_work_ / (double(states_) * full), states_};
  }

 private:
  // Peak k0 of |n| and the active range 1..K_a (K_a the last size with |n_k| > max(ν_k, 1e-300 |n_k0|)).
  void find_active_range(std::span<const double> n) {
    peak_ = 1;
    for (std::size_t k = 1; k <= size_; ++k)
      if (std::abs(n[k - 1]) > std::abs(n[peak_ - 1])) peak_ = k;
    const double floor = 1e-300 * std::abs(n[peak_ - 1]);
    active_ = 1;
    for (std::size_t k = size_; k >= 1; --k)
      if (std::abs(n[k - 1]) > floor && (negligible_.empty() || std::abs(n[k - 1]) > negligible_[k - 1])) {
        active_ = k;
        break;
      }
  }

  static double work(std::size_t length) { return double(length) * std::log2(double(length)); }

  // Slowest decay rate of |n| beyond its peak with growth allowance G = 10, sampled at ≤ 1024 sizes
  // (the allowance absorbs what the sampling misses; overflow is excluded when tilting).
  double decay_rate(std::span<const double> n) const {
    double rate = INFINITY;
    const double log_reference = std::log(10.0 * std::abs(n[peak_ - 1]));
    auto probe = [&](std::size_t k) {
      if (n[k - 1] != 0.0) rate = std::min(rate, (log_reference - std::log(std::abs(n[k - 1]))) / double(k - peak_));
    };
    const std::size_t stride = std::max<std::size_t>(1, (active_ - peak_) / 1024);
    for (std::size_t k = peak_ + 1; k <= active_; k += stride) probe(k);
    if (active_ > peak_) probe(active_);
    return std::isfinite(rate) && n[peak_ - 1] != 0.0 ? std::max(rate, 0.0) : 0.0;
  }

  // Caches, for the state n: the active range, the tilt, the spectra the gain needs, c(n).
  void prepare(std::span<const double> n) {
    if (std::memcmp(n.data(), cached_n_.data(), sizeof(double) * size_) == 0) return;
    std::copy(n.begin(), n.end(), cached_n_.begin());
    newton_spectra_ready_ = false;
    find_active_range(n);
    length_ = fft_.length_for(active_);
    ++states_, active_sum_ += active_, fft_work_ += work(length_);
    tilt_ = decay_rate(n);
    plain_bound_ = kernel_.roundoff_bound(n, active_);
    use_tilted_ = tilt_ > 0.0;
    use_plain_ = true;
    if (use_tilted_) {
      // x̃_k = n_k e^{θ(k-k0)}: the weight by recurrence while it is representable, else in logs.
      const double step = std::exp(tilt_);
      double weight = std::exp(-tilt_ * double(peak_ - 1));
      for (std::size_t k = 1; k <= active_; ++k, weight *= step) {
        const double x = n[k - 1];
        tilted_n_[k - 1] = weight < 1e280 ? x * weight
                           : x == 0.0     ? 0.0
                                          : std::copysign(std::exp(std::log(std::abs(x)) + tilt_ * (double(k) - double(peak_))), x);
      }
      tilted_bound_ = kernel_.roundoff_bound(tilted_n_, active_);
      kernel_.transform(tilted_n_, active_, length_, fft_, tilted_);
      // The tilted bound exceeds the plain one for sums s < 2k0 + ln(ratio)/θ (ratio at s = 2k0):
      // the plain convolution is needed only there, so only sizes up to that enter it (a shorter FFT).
      const double ratio = tilted_bound_ / plain_bound_;
      use_plain_ = ratio > 1.0;
      const double crossover = 2.0 * double(peak_) + std::log(std::max(ratio, 1.0)) / tilt_;
      plain_support_ = std::min<double>(double(active_), std::ceil(crossover));
    } else {
      plain_support_ = active_;
    }
    // Sums s ≤ plain_support + 1 have every pair inside the support (all sums when it is the whole range).
    plain_valid_ = plain_support_ == active_ ? 2 * active_ : plain_support_ + 1;
    if (use_plain_) {
      plain_length_ = fft_.length_for(plain_support_);
      kernel_.transform(n, plain_support_, plain_length_, fft_, plain_);
    }
    kernel_.collision_rates(n, active_, cutoff_, rate_n_, size_);  // c_k for every size (J's diagonal)
  }

  AggregationModel model_;  // a copy: the rates may outlive the discretisation that made them
  bool cutoff_;
  SeparableKernel kernel_;
  std::unique_ptr<SeparableKernel> newton_kernel_;  // lower-rank form for J·v (approximated kernels)
  FftConvolution fft_;
  std::vector<FftConvolution::Spectrum> plain_, tilted_, newton_plain_;
  FftConvolution::Spectrum accumulator_;
  std::vector<double> kernel_diagonal_, kernel_monomer_, kernel_subdiagonal_;  // K̃_kk, K̃_k1, K̃_{k,k-1}
  std::vector<double> cached_n_, rate_n_, rate_v_, tilted_n_, conv_, tilted_conv_;
  std::vector<double> negligible_;  // ν_k (empty: none)
  long states_ = 0;
  std::size_t active_sum_ = 0;
  double fft_work_ = 0.0;
  double tilt_ = 0.0, plain_bound_ = 0.0, tilted_bound_ = 0.0;
  bool use_plain_ = true, use_tilted_ = false, newton_spectra_ready_ = false;
  std::size_t active_ = 1, length_ = 0, peak_ = 1, plain_support_ = 1, plain_valid_ = 2, plain_length_ = 0;
};

}  // namespace

std::unique_ptr<Rates> make_fast_rates(const AggregationModel& model, double lowrank_tolerance,
                                       double jacobian_tolerance) {
  return std::make_unique<FastRates>(model, lowrank_tolerance, jacobian_tolerance);
}

}  // namespace aggkit

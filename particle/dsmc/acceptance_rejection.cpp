#include "particle/dsmc/acceptance_rejection.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

#include "particle/dsmc/population_control.hpp"

namespace aggkit::dsmc {

namespace {
// Row sums are refreshed from the integer counts this often, so round-off in the incremental updates
// never accumulates (it only affects the choice among bins, never the acceptance test).
constexpr std::uint64_t refresh_interval = 1 << 16;
}  // namespace

AcceptanceRejection::AcceptanceRejection(InteractionKernel kernel, std::uint64_t bucket_limit)
    : kernel_(kernel), table_(kernel_), population_(bucket_limit), majorant_(max_bins * max_bins, 0.0),
      diagonal_(max_bins, 0.0), zeros_(max_bins, 0.0), count_(max_bins, 0.0), row_(max_bins, 0.0), weight_(max_bins, 0.0) {}

void AcceptanceRejection::ensure_bins(std::size_t bins) {
  if (bins <= known_) return;
  for (; known_ < bins; ++known_) {
    const std::size_t c = known_;
    const std::uint64_t c_low = bin_low(c), c_high = bin_high(c);
    for (std::size_t b = 0; b <= c; ++b) {
      const std::uint64_t b_low = bin_low(b), b_high = bin_high(b);
      double bound = 0.0;
      // A cutoff forbids every pair of the two bins when even the smallest sizes exceed it.
      if (kernel_.cutoff() == 0 || b_low + c_low <= kernel_.cutoff())
        bound = std::max({kernel_.raw(b_low, c_low), kernel_.raw(b_low, c_high), kernel_.raw(b_high, c_low),
                          kernel_.raw(b_high, c_high)});
      majorant_[b * max_bins + c] = majorant_[c * max_bins + b] = bound;
    }
    diagonal_[c] = bound(c, c);
  }
  recompute_rows();  // the new bins' rows see the particles already present
}

void AcceptanceRejection::change(std::size_t bin, double delta) {
  // Deferred to trial_weight(), which applies the (at most three) changes of an event in one pass.
  for (std::size_t k = 0; k < pending_count_; ++k)
    if (pending_[k].bin == bin) {
      pending_[k].delta += delta;
      count_[bin] += delta;
      dirty_ = true;
      return;
    }
  if (pending_count_ == pending_.size()) apply_pending();
  pending_[pending_count_++] = {bin, delta};
  count_[bin] += delta;
  dirty_ = true;
}

void AcceptanceRejection::apply_pending() {
  const std::size_t n = known_;
  for (std::size_t k = 0; k < pending_count_; ++k) {
    const double delta = pending_[k].delta;
    const double* column = &majorant_[pending_[k].bin * max_bins];  // symmetric: row `bin` is column `bin`
    for (std::size_t b = 0; b < n; ++b) row_[b] += delta * column[b];
  }
  pending_count_ = 0;
}

void AcceptanceRejection::recompute_rows() {
  const std::size_t n = population_.bins();
  for (std::size_t c = 0; c < n; ++c) count_[c] = double(population_.count(c));
  for (std::size_t b = 0; b < known_; ++b) {
    double sum = 0.0;
    for (std::size_t c = 0; c < n; ++c) sum += bound(b, c) * count_[c];
    row_[b] = sum;
  }
  pending_count_ = 0;
  dirty_ = true;
  events_since_refresh_ = 0;
}

void AcceptanceRejection::insert(std::uint64_t size, std::uint64_t count) {
  const std::size_t bin = bin_of(size);
  if (bin >= known_) ensure_bins(bin + 1);
  population_.add(size, count);
  change(bin, double(count));
}

void AcceptanceRejection::add(std::uint64_t size, std::uint64_t count) { insert(size, count); }

double AcceptanceRejection::trial_weight() {
  if (!dirty_) return total_weight_;
  // One pass over the bins: the pending row changes of the last event (unused slots add 0 × a row of zeros),
  // then the weights n_b (row_b - K̄(b,b)).
  const double* column[3];
  double delta[3];
  for (std::size_t k = 0; k < 3; ++k) {
    column[k] = k < pending_count_ ? &majorant_[pending_[k].bin * max_bins] : zeros_.data();
    delta[k] = k < pending_count_ ? pending_[k].delta : 0.0;
  }
  pending_count_ = 0;
  const std::size_t n = known_;  // row_, weight_, count_ and diagonal_ hold max_bins entries (a multiple of 4)
  // Two bins at a time in vector registers (GCC's vector extensions: SSE2 on x86-64); each lane does the
  // scalar operations in the scalar order, so the values are the same bits as one bin at a time.
  using Pair = double __attribute__((vector_size(2 * sizeof(double))));
  const auto load = [](const double* p) {
    Pair v;
    std::memcpy(&v, p, sizeof v);
    return v;
  };
  const Pair d0 = {delta[0], delta[0]}, d1 = {delta[1], delta[1]}, d2 = {delta[2], delta[2]}, zero = {0.0, 0.0};
  Pair low = zero, high = zero;  // four sums: lane l of low adds the bins b + l, of high the bins b + 2 + l
  for (std::size_t b = 0; b < n; b += 2) {
    const Pair row = load(&row_[b]) + (d0 * load(&column[0][b]) + d1 * load(&column[1][b]) + d2 * load(&column[2][b]));
    const Pair w = load(&count_[b]) * (row - load(&diagonal_[b]));
    const Pair positive = w > zero ? w : zero;
    std::memcpy(&row_[b], &row, sizeof row);
    std::memcpy(&weight_[b], &positive, sizeof positive);
    if ((b & 2) == 0)
      low += positive;
    else
      high += positive;
  }
  const double partial[4] = {low[0], low[1], high[0], high[1]};
  total_weight_ = (partial[0] + partial[1]) + (partial[2] + partial[3]);
  dirty_ = false;
  return total_weight_;
}

TrialOutcome AcceptanceRejection::trial(double lambda, Random& random) {
  const std::size_t n = population_.bins();
  // First bin by its weight, second by K̄(b, c)(n_c - δ_bc); a round-off overrun takes the last candidate.
  double u = random.uniform() * total_weight_;
  std::size_t b = 0, last = 0;
  for (; b < n; ++b) {
    if (weight_[b] <= 0.0) continue;
    last = b;
    if (u < weight_[b]) break;
    u -= weight_[b];
  }
  if (b == n) b = last;
  const std::uint64_t n_b = population_.count(b);
  double v = random.uniform() * std::max(0.0, row_[b] - diagonal_[b]);
  const double* bounds = &majorant_[b * max_bins];
  std::size_t c = 0;
  last = n;
  for (; c < n; ++c) {
    const double w = bounds[c] * (count_[c] - (c == b ? 1.0 : 0.0));
    if (w <= 0.0) continue;
    last = c;
    if (v < w) break;
    v -= w;
  }
  if (c == n) c = last;
  if (c == n) return TrialOutcome::rejected;  // no partner (cannot happen while W > 0)

  const std::uint64_t first_rank = random.below(n_b);
  std::uint64_t second_rank;
  if (c == b) {
    second_rank = random.below(n_b - 1);
    if (second_rank >= first_rank) ++second_rank;
  } else {
    second_rank = random.below(population_.count(c));
  }
  const auto p = population_.pick(b, first_rank);
  const auto q = population_.pick(c, second_rank);

  const double k = table_(p.size, q.size);
  const double majorant = bound(b, c);
  if (k > majorant * (1.0 + 1e-12))
    throw std::runtime_error("dsmc: kernel K(" + std::to_string(p.size) + ", " + std::to_string(q.size) +
                             ") exceeds its bin majorant; the kernel is not quasi-convex in each size");
  // One uniform number decides all three outcomes ([Kalinov2022, Sec. 3]): u' in [0, (1+λ) K̄).
  const double x = random.uniform() * (1.0 + lambda) * majorant;
  if (!(x < (1.0 + lambda) * k)) return TrialOutcome::rejected;

  // Remove the pair (two individually stored particles of one bin: the higher index first).
  if (p.bin == q.bin && p.large_index != BinnedPopulation::npos && q.large_index != BinnedPopulation::npos &&
      p.large_index < q.large_index) {
    population_.remove(q);
    population_.remove(p);
  } else {
    population_.remove(p);
    population_.remove(q);
  }
  change(p.bin, -1.0);
  change(q.bin, -1.0);
  const std::uint64_t merged = p.size + q.size;
  TrialOutcome outcome;
  if (x < k) {
    if (kernel_.leaves(merged)) {
      leaked_ += merged;
      outcome = TrialOutcome::leaked;
    } else {
      insert(merged, 1);
      outcome = TrialOutcome::aggregated;
    }
  } else {
    insert(1, merged);  // shattering: i + j monomers, one bucket update
    outcome = TrialOutcome::shattered;
  }
  if (++events_since_refresh_ >= refresh_interval) recompute_rows();
  return outcome;
}

void AcceptanceRejection::duplicate() {
  population_.duplicate();
  leaked_ *= 2;
  recompute_rows();
}

void AcceptanceRejection::halve(Random& random) {
  population_.halve(random);
  leaked_ = halve_count(leaked_, random);
  recompute_rows();
}

}  // namespace aggkit::dsmc

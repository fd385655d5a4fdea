// The slot tables of the binned majorant (particle/dsmc/slot_majorant.hpp) against a direct sum over slot
// pairs, and the acceptance-rejection stepper built on them against the exact pair process: the first
// accepted pair of a fixed population is (i, j) with probability K_ij n_i (n_j - δ_ij) / Σ, and the trials it
// takes average W / Σ, so that their time steps 2V / ((1+λ) W) add up to the exact mean waiting time
// 2V / ((1+λ) Σ) — the empty slots change how many trials an event takes, never which events happen or when.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "particle/dsmc/acceptance_rejection.hpp"
#include "particle/dsmc/random.hpp"
#include "particle/dsmc/slot_majorant.hpp"
#include "solvers/kernels.hpp"
#include "solvers/model.hpp"

using namespace aggkit;

namespace {

std::vector<double> corner_majorant(const Kernel& kernel, std::size_t bins) {
  std::vector<double> majorant(dsmc::max_bins * dsmc::max_bins, 0.0);
  for (std::size_t b = 0; b < bins; ++b)
    for (std::size_t c = 0; c < bins; ++c) {
      const std::uint64_t bl = dsmc::bin_low(b), bh = dsmc::bin_high(b), cl = dsmc::bin_low(c), ch = dsmc::bin_high(c);
      majorant[b * dsmc::max_bins + c] = std::max({kernel(bl, cl), kernel(bl, ch), kernel(bh, cl), kernel(bh, ch)});
    }
  return majorant;
}

}  // namespace

TEST_CASE("dsmc: the slot tables choose each bin pair with its share of the slot pairs' majorant") {
  const Kernel kernel = Kernel::ballistic();
  // Empty bins, a bin of one particle, bins of thousands: every kind of capacity and diagonal.
  std::vector<std::uint64_t> counts(dsmc::max_bins, 0);
  const std::vector<std::uint64_t> occupied{5000, 0, 1, 700, 0, 0, 2, 40, 1, 0, 0, 3};
  std::copy(occupied.begin(), occupied.end(), counts.begin());
  const std::size_t bins = occupied.size();
  const std::vector<double> majorant = corner_majorant(kernel, bins);
  dsmc::SlotMajorant slots;
  slots.set_capacities(counts.data(), bins);
  slots.build(majorant.data(), counts.data());

  // Direct sums over the ordered pairs of distinct slots.
  std::vector<std::vector<double>> pair(bins, std::vector<double>(bins, 0.0));
  std::vector<double> first(bins, 0.0);
  double total = 0.0, real = 0.0;
  for (std::size_t b = 0; b < bins; ++b) {
    CHECK(slots.capacity(b) >= counts[b]);
    CHECK(slots.holds(b, counts[b]));
    for (std::size_t c = 0; c < bins; ++c) {
      const double m_b = double(slots.capacity(b)), m_c = double(slots.capacity(c));
      pair[b][c] = majorant[b * dsmc::max_bins + c] * m_b * (b == c ? m_b - 1.0 : m_c);
      first[b] += pair[b][c];
      real += majorant[b * dsmc::max_bins + c] * double(counts[b]) * double(b == c ? counts[b] - std::min<std::uint64_t>(counts[b], 1) : counts[c]);
    }
    total += first[b];
  }
  CHECK(slots.total() == Approx(total).epsilon(1e-13));
  CHECK(slots.particles_interact() == (real > 0.0));
  CHECK_FALSE(slots.holds(bins, 0));  // beyond the tables: a rebuild

  // Each bin's share of u in [0, 1), on a grid of 2^20 points: an alias table's cell boundaries cost at most
  // 2 grid points per cell, so every share is within 2·bins / 2^20 of its weight's; zero weights never drawn.
  const int grid = 1 << 20;
  std::vector<double> share(bins, 0.0);
  std::vector<std::vector<double>> row_share(bins, std::vector<double>(bins, 0.0));
  for (int i = 0; i < grid; ++i) {
    const double u = (i + 0.5) / grid;
    share[slots.first(u)] += 1.0 / grid;
    for (std::size_t b = 0; b < bins; ++b)
      if (first[b] > 0.0) row_share[b][slots.second(b, u)] += 1.0 / grid;
  }
  const double tolerance = 2.0 * double(bins) / grid;
  for (std::size_t b = 0; b < bins; ++b) {
    INFO("bin " << b);
    CHECK(std::abs(share[b] - first[b] / total) <= tolerance);
    if (first[b] == 0.0) CHECK(share[b] == 0.0);
    if (first[b] > 0.0)
      for (std::size_t c = 0; c < bins; ++c) {
        CHECK(std::abs(row_share[b][c] - pair[b][c] / first[b]) <= tolerance);
        if (pair[b][c] == 0.0) CHECK(row_share[b][c] == 0.0);
      }
  }
  for (double u : {0.0, 0.999999999999, 1.0 - 0x1.0p-53}) {  // the ends of [0, 1)
    CHECK(first[slots.first(u)] > 0.0);
    for (std::size_t b = 0; b < bins; ++b)
      if (first[b] > 0.0) CHECK(pair[b][slots.second(b, u)] > 0.0);
  }
}

TEST_CASE("dsmc: the first accepted pair of the slot majorant follows the exact pair process") {
  // Sizes whose pairwise sums are distinct, so the merged size names the pair; 3000 is stored one by one.
  const std::vector<std::pair<std::uint64_t, std::uint64_t>> population{{1, 50}, {2, 20}, {7, 5}, {100, 3}, {3000, 1}};
  const Kernel kernel = Kernel::sum();  // cheap to tabulate: a fresh stepper per repetition
  const dsmc::InteractionKernel interaction(kernel, false, Truncation::drop, 0);
  std::map<std::uint64_t, double> expected;  // merged size -> Σ over ordered pairs of K
  double sum = 0.0;
  for (const auto& [i, n_i] : population)
    for (const auto& [j, n_j] : population) {
      const double rate = kernel(i, j) * double(n_i) * double(i == j ? n_j - 1 : n_j);
      if (rate > 0.0) expected[i + j] += rate;
      sum += rate;
    }
  dsmc::Random random(dsmc::run_seed(11, 0));
  const int repetitions = 20000;
  std::map<std::uint64_t, double> seen;
  double trials_over_mean = 0.0, squares = 0.0;
  for (int r = 0; r < repetitions; ++r) {
    dsmc::AcceptanceRejection stepper(interaction, 1024);
    for (const auto& [size, count] : population) stepper.add(size, count);
    const double weight = stepper.trial_weight();
    std::uint64_t trials = 1;
    while (stepper.trial(0.0, random) == dsmc::TrialOutcome::rejected) {
      REQUIRE(stepper.trial_weight() == weight);  // nothing changed: the same tables
      ++trials;
    }
    const double x = double(trials) * sum / weight;  // mean 1
    trials_over_mean += x;
    squares += x * x;
    std::uint64_t merged = 0;
    stepper.for_each_group([&](std::uint64_t size, std::uint64_t count) {
      for (const auto& [s, n] : population)
        if (s == size && count > n) merged = size;
      if (std::none_of(population.begin(), population.end(), [&](const auto& g) { return g.first == size; })) merged = size;
    });
    seen[merged] += 1.0;
  }
  // Chi-square over the 14 possible pairs (13 degrees of freedom: mean 13, standard deviation 5.1; 45 is
  // p ~ 1e-5).
  double chi2 = 0.0;
  for (const auto& [merged, rate] : expected) {
    const double e = repetitions * rate / sum;
    chi2 += (seen[merged] - e) * (seen[merged] - e) / e;
  }
  CHECK(seen.size() == expected.size());
  CHECK(chi2 < 45.0);
  // The trials are geometric with success probability Σ / W: trials × Σ / W has mean 1; 5 standard errors.
  const double mean = trials_over_mean / repetitions;
  const double error = std::sqrt((squares / repetitions - mean * mean) / repetitions);
  CHECK(std::abs(mean - 1.0) < 5.0 * error);
}

#pragma once
// Acceptance-rejection DSMC with a binned majorant kernel (the `ar` method).
//
// The textbook method ([Kalinov2022, Algorithms 1 and 3]; [Gillespie1975]) draws a uniform pair and
// accepts it with K_ij / K_max: its cost per accepted event grows with K_max / mean K, i.e. with the
// spread of sizes. Here the bound is a majorant kernel K̄(b, c) >= K_ij, constant on pairs of size bins
// (size_bins.hpp) — the "majorant kernel" idea of Eibeck & Wagner [Eibeck2001] in the binned form of
// Michelotti, Heath & West [Michelotti2013]. The majorant
// pair process is sampled exactly: bin b with weight n_b Σ_c K̄(b,c)(n_c - δ_bc), bin c with weight
// K̄(b,c)(n_c - δ_bc), then a uniform particle in each; the pair is accepted with K_ij / K̄(b, c). The
// row sums Σ_c K̄(b,c) n_c are updated in O(#bins) per event, so the cost per trial is O(#bins + log B)
// and the acceptance probability is bounded below by the kernel's variation across two bins — neither
// depends on N nor on the spread of sizes (the number of bins grows only like log2 of the largest size).
//
// K̄(b, c) is the kernel's maximum over the four corners of the bin pair. That is exact for kernels that are
// quasi-convex in each size (decreasing then increasing, or monotone): constant, sum, product, linear,
// genproduct, brownian ((i/j)^a + (j/i)^a in i is minimal at i = j) and ballistic (d log K / d i changes
// sign once: with z = (i/j)^{1/3} the sign is that of (2/3)(z - z^2 + z^3) - 1/2, increasing in z). Every
// accepted pair checks K_ij <= K̄; a user kernel that violates the bound stops the run with an error.
#include <array>
#include <memory>
#include <vector>

#include "particle/dsmc/binned_population.hpp"
#include "particle/dsmc/kernel_table.hpp"
#include "particle/dsmc/stepper.hpp"

namespace aggkit::dsmc {

class AcceptanceRejection final : public Stepper {
 public:
  AcceptanceRejection(InteractionKernel kernel, std::uint64_t bucket_limit);

  void add(std::uint64_t size, std::uint64_t count) override;
  double trial_weight() override;
  TrialOutcome trial(double lambda, Random& random) override;
  void duplicate() override;
  void halve(Random& random) override;
  std::uint64_t particles() const override { return population_.particles(); }
  void for_each_group(const std::function<void(std::uint64_t, std::uint64_t)>& f) const override {
    population_.for_each_group(f);
  }
  std::uint64_t leaked_mass() const override { return leaked_; }
  std::size_t bins() const { return population_.bins(); }

  void save(StateWriter& out) const override;
  void restore(StateReader& in) override;

 private:
  double bound(std::size_t b, std::size_t c) const { return majorant_[b * max_bins + c]; }
  void ensure_bins(std::size_t bins);  // majorant entries for bins < `bins`
  void change(std::size_t bin, double delta);  // n_bin += delta: the row sums follow in trial_weight()
  void apply_pending();
  void insert(std::uint64_t size, std::uint64_t count);
  void recompute_rows();

  InteractionKernel kernel_;
  KernelTable table_;             // K_ij for i, j <= KernelTable::sizes, equal to kernel_(i, j)
  BinnedPopulation population_;
  std::vector<double> majorant_;  // max_bins × max_bins, filled for bins < known_
  std::vector<double> diagonal_;  // K̄(b, b)
  std::vector<double> zeros_;     // a row of zeros (unused pending slots)
  std::size_t known_ = 0;
  std::vector<double> count_;     // n_b as a double (exact below 2^53)
  std::vector<double> row_;       // row_[b] = Σ_c K̄(b,c) n_c, up to the pending changes
  std::vector<double> weight_;    // n_b (row_b - K̄(b,b)), valid when !dirty_
  struct Change {
    std::size_t bin;
    double delta;
  };
  std::array<Change, 3> pending_{};  // count changes not yet applied to row_ (an event makes at most three)
  std::size_t pending_count_ = 0;
  double total_weight_ = 0.0;
  bool dirty_ = true;
  std::uint64_t leaked_ = 0;
  std::uint64_t events_since_refresh_ = 0;
};

}  // namespace aggkit::dsmc

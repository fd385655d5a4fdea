#pragma once
// Acceptance-rejection DSMC with a binned majorant kernel (the `ar` method).
//
// The textbook method ([Kalinov2022, Algorithms 1 and 3]; [Gillespie1975]) draws a uniform pair and
// accepts it with K_ij / K_max: its cost per accepted event grows with K_max / mean K, i.e. with the
// spread of sizes. Here the bound is a majorant kernel K̄(b, c) >= K_ij, constant on pairs of size bins
// (size_bins.hpp) — the "majorant kernel" idea of Eibeck & Wagner [Eibeck2001] in the binned form of
// Michelotti, Heath & West [Michelotti2013]. The majorant
// pair process is sampled exactly on the population padded with empty slots (slot_majorant.hpp): bin b with
// weight m_b Σ_c K̄(b,c)(m_c - δ_bc), bin c with weight K̄(b,c)(m_c - δ_bc), then a uniform slot in each; a pair
// with an empty slot is rejected, a pair of particles accepted with K_ij / K̄(b, c). The capacities m_b >= n_b
// change only when a count leaves its band, so the tables are rebuilt in O(#bins²) now and then instead of
// the row sums Σ_c K̄(b,c) n_c being updated at every event; the cost per trial is O(1) for the bin pair (two
// alias-table draws) + O(log B) within the bins, and the acceptance probability is bounded below by the
// kernel's variation across two bins times the fill of the two bins' slots (n_b / m_b, which the rebuilds keep
// near 1 in the populous bins) — neither depends on N nor on the spread of sizes.
//
// K̄(b, c) is the kernel's maximum over the four corners of the bin pair. That is exact for kernels that are
// quasi-convex in each size (decreasing then increasing, or monotone): constant, sum, product, linear,
// genproduct, brownian ((i/j)^a + (j/i)^a in i is minimal at i = j) and ballistic (d log K / d i changes
// sign once: with z = (i/j)^{1/3} the sign is that of (2/3)(z - z^2 + z^3) - 1/2, increasing in z). Every
// accepted pair checks K_ij <= K̄; a user kernel that violates the bound stops the run with an error.
#include <memory>
#include <vector>

#include "particle/dsmc/binned_population.hpp"
#include "particle/dsmc/kernel_table.hpp"
#include "particle/dsmc/slot_majorant.hpp"
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
  void insert(std::uint64_t size, std::uint64_t count);
  void touched(std::size_t bin) {  // a count changed: rebuild the slot tables once it leaves its band
    if (!slots_.holds(bin, population_.count(bin))) dirty_ = true;
  }
  void rebuild();  // capacities from the counts, then the slot tables
  const std::uint64_t* counts();  // the counts of the population's bins, contiguous

  InteractionKernel kernel_;
  KernelTable table_;             // K_ij for i, j <= KernelTable::sizes, equal to kernel_(i, j)
  BinnedPopulation population_;
  std::vector<double> majorant_;  // max_bins × max_bins, filled for bins < known_
  std::size_t known_ = 0;
  SlotMajorant slots_;
  std::vector<std::uint64_t> counts_;  // scratch for counts()
  bool dirty_ = true;                  // the slot tables must be rebuilt before the next trial
  std::uint64_t leaked_ = 0;
};

}  // namespace aggkit::dsmc

#pragma once
// Fast (two-stage) DSMC, the `fast` method ([Kalinov2022, Algorithms 2 and 4]): the first particle i is
// chosen with probability S_i / Σ S, S_i = Σ_{j != i} K_ij, then the partner j with probability K_ij / S_i
// — no rejection. Particles of one size <= B share a group (count + the per-particle rate S of that size,
// [Kalinov2022, Sec. 4]); larger particles are groups of their own. Keeping every S exact costs O(D) kernel
// evaluations per event (D = number of groups), the price of this method that the paper's run times show
// ([Kalinov2022, Tables 3–4]); it is kept as an independent check of the majorant sampler of
// acceptance_rejection.hpp, which is the fast one here.
#include <cstddef>
#include <vector>

#include "particle/dsmc/stepper.hpp"

namespace aggkit::dsmc {

class FastDsmc final : public Stepper {
 public:
  FastDsmc(InteractionKernel kernel, std::uint64_t bucket_limit);

  void add(std::uint64_t size, std::uint64_t count) override { change(size, std::int64_t(count)); }
  double trial_weight() override;
  TrialOutcome trial(double lambda, Random& random) override;
  void duplicate() override;
  void halve(Random& random) override;
  std::uint64_t particles() const override { return particles_; }
  void for_each_group(const std::function<void(std::uint64_t, std::uint64_t)>& f) const override;
  std::uint64_t leaked_mass() const override { return leaked_; }

  void save(StateWriter& out) const override;
  void restore(StateReader& in) override;

 private:
  struct Group {
    std::uint64_t size;
    std::uint64_t count;
    double rate;  // S of one particle of this group: Σ over the other particles of K(size, ·)
  };
  // n_size += delta for a bucketed size, or one individual particle added (delta = +1) / removed (index).
  void change(std::uint64_t size, std::int64_t delta, std::size_t group = npos);
  void remove_group(std::size_t group);
  void recompute_rates();
  static constexpr std::size_t npos = std::size_t(-1);

  InteractionKernel kernel_;
  std::uint64_t limit_;
  std::vector<Group> groups_;
  std::vector<std::size_t> slot_;  // slot_[s]: group of bucketed size s, or npos
  std::uint64_t particles_ = 0;
  std::uint64_t leaked_ = 0;
  double total_weight_ = 0.0;
  std::uint64_t events_since_refresh_ = 0;
};

}  // namespace aggkit::dsmc

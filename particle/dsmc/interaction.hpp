#pragma once
// What one DSMC collision does ([Kalinov2022, Sec. 3, PairInteraction of Algorithm 3]): a pair (i, j)
// interacts at rate (1+λ)K_ij; it shatters into i+j monomers with probability λ/(1+λ), else it merges into
// one cluster of size i+j. Optional truncation, as for the kinetic equations (solvers/model.hpp): `cutoff`
// sets K_ij = 0 for i+j > N; `drop` removes merged clusters larger than N (their mass is counted as leaked).
#include <cstdint>

#include "solvers/kernels.hpp"
#include "solvers/model.hpp"

namespace aggkit::dsmc {

enum class TrialOutcome { rejected, aggregated, shattered, leaked };

class InteractionKernel {
 public:
  InteractionKernel(const Kernel& kernel, bool truncate, Truncation policy, std::uint64_t size)
      : kernel_(kernel),
        cutoff_(truncate && policy == Truncation::cutoff ? size : 0),
        drop_(truncate && policy == Truncation::drop ? size : 0) {}

  // K_ij of the simulated system (0 for pairs beyond a cutoff).
  double operator()(std::uint64_t i, std::uint64_t j) const {
    if (cutoff_ != 0 && i + j > cutoff_) return 0.0;
    return kernel_(i, j);
  }
  // The kernel itself (majorants bound it; a cutoff only lowers it).
  double raw(std::uint64_t i, std::uint64_t j) const { return kernel_(i, j); }
  std::uint64_t cutoff() const { return cutoff_; }         // 0: none
  bool leaves(std::uint64_t merged) const { return drop_ != 0 && merged > drop_; }

 private:
  const Kernel& kernel_;
  std::uint64_t cutoff_;
  std::uint64_t drop_;
};

}  // namespace aggkit::dsmc

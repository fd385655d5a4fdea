#pragma once
// The state of one engine at one output time (one realization), as the observables read it. A kinetic
// engine gives its size distribution n_1..n_N (per unit volume) and the mass that left through the
// truncation; a particle engine gives the cluster-size distribution per initial particle and, through
// particles(), its configuration (validation/observables/particle_view.hpp). What an observable reads of
// a state is declared with it in the registry (observable.hpp), so the harness asks only for that.
#include <cstddef>
#include <span>
#include <vector>

namespace aggkit {

class ParticleView;

class ObservedState {
 public:
  virtual ~ObservedState() = default;
  virtual std::vector<double> distribution() const = 0;  // n_1..n_N
  // M_p = Σ_k k^p n_k and n_k; by default from distribution(). A state that knows its moments in closed
  // form (the untruncated exact solutions, whose tails go beyond any N) gives them here.
  virtual double moment(double p) const;
  virtual double density(std::size_t k) const;
  virtual double leaked_mass() const { return 0.0; }  // mass that left through the truncation so far
  virtual const ParticleView* particles() const { return nullptr; }  // the configuration, if there is one
};

// A state given by its densities n_1..n_N (a view: the densities must outlive it).
class DensityState final : public ObservedState {
 public:
  DensityState(std::span<const double> n, double leaked_mass) : n_(n), leaked_mass_(leaked_mass) {}
  std::vector<double> distribution() const override { return {n_.begin(), n_.end()}; }
  double moment(double p) const override;
  double density(std::size_t k) const override { return k >= 1 && k <= n_.size() ? n_[k - 1] : 0.0; }
  double leaked_mass() const override { return leaked_mass_; }

 private:
  std::span<const double> n_;
  double leaked_mass_;
};

}  // namespace aggkit

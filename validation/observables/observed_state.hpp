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
class Discretisation;

class ObservedState {
 public:
  virtual ~ObservedState() = default;
  virtual std::vector<double> distribution() const = 0;  // n_1..n_N (a graded grid: its classes' numbers)
  // The sizes of distribution()'s entries where they are not 1..N: a graded grid's pivots
  // (solvers/size_grid.hpp), whose entries are the numbers of clusters each pivot stands for.
  virtual std::vector<double> sizes() const { return {}; }
  // M_p = Σ_k k^p n_k and n_k; by default from distribution(). A state that knows its moments in closed
  // form (the untruncated exact solutions, whose tails go beyond any N) gives them here.
  virtual double moment(double p) const;
  virtual double density(std::size_t k) const;
  virtual double leaked_mass() const { return 0.0; }  // mass that left through the truncation so far
  virtual const ParticleView* particles() const { return nullptr; }  // the configuration, if there is one
};

// A state given by its densities n_1..n_N, or on a graded grid by the numbers N_i at the pivots `sizes`
// (views: both must outlive it) and the discretisation they are on. M_p = Σ x_i^p N_i; n_k is the density
// per unit size f_i the numbers stand for at a pivot (Discretisation::densities, computed at the first
// density() call) and log-linear between pivots (linear where an end is ≤ 0), the local exponential those
// densities are read with; without a discretisation, N_i / Δ_i.
class DensityState final : public ObservedState {
 public:
  DensityState(std::span<const double> n, double leaked_mass, std::span<const double> sizes = {},
               const Discretisation* grid = nullptr)
      : n_(n), leaked_mass_(leaked_mass), sizes_(sizes), grid_(grid) {}
  std::vector<double> distribution() const override { return {n_.begin(), n_.end()}; }
  std::vector<double> sizes() const override { return {sizes_.begin(), sizes_.end()}; }
  double moment(double p) const override;
  double density(std::size_t k) const override;
  double leaked_mass() const override { return leaked_mass_; }

 private:
  std::span<const double> n_;
  double leaked_mass_;
  std::span<const double> sizes_;
  const Discretisation* grid_;
  mutable std::vector<double> densities_;  // per pivot, once asked for
};

// The density at size k of a graded grid's densities f_i at pivots x_i (as DensityState::density): 0
// outside [x_1, x_M].
double density_on_pivots(std::span<const double> densities, std::span<const double> sizes, double k);

}  // namespace aggkit

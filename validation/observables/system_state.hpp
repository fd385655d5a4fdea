#pragma once
// The system at one output time as an engine reports it. Observables are evaluated on this interface, so
// an engine that knows its moments in closed form (the exact solutions) and one that only has densities
// (CVODE, and later DSMC) are observed the same way.
#include <cstddef>
#include <span>
#include <vector>

namespace aggkit {

class SystemState {
 public:
  virtual ~SystemState() = default;
  virtual double moment(double p) const = 0;           // M_p = Σ_k k^p n_k
  virtual double density(std::size_t k) const = 0;     // n_k (k >= 1)
  virtual double leaked_mass() const = 0;              // mass that left through the truncation so far
  virtual std::vector<double> distribution() const = 0;  // n_1..n_N
  // A stochastic engine's ensemble: the state above is the mean of `realisations()` independent runs, each
  // available on its own so that observables get a standard error. A deterministic state is its own only one.
  virtual std::size_t realisations() const { return 1; }
  virtual const SystemState& realisation(std::size_t) const { return *this; }
  // Particle-level observables; a state of densities has no particle count or velocities (NaN), and its mean
  // cluster size is the number-average size M1/M0.
  virtual double clusters() const;
  virtual double kinetic_energy() const;
  virtual double mean_cluster_size() const { return moment(1) / moment(0); }
};

// A state given by its densities n_1..n_N (a view: the densities must outlive it).
class DensityState final : public SystemState {
 public:
  DensityState(std::span<const double> n, double leaked_mass) : n_(n), leaked_mass_(leaked_mass) {}
  double moment(double p) const override;
  double density(std::size_t k) const override { return k >= 1 && k <= n_.size() ? n_[k - 1] : 0.0; }
  double leaked_mass() const override { return leaked_mass_; }
  std::vector<double> distribution() const override { return {n_.begin(), n_.end()}; }

 private:
  std::span<const double> n_;
  double leaked_mass_;
};

}  // namespace aggkit

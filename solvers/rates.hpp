#pragma once
// Right-hand side of the aggregation-shattering equations (solvers/model.hpp) and its Jacobian.
// Two implementations: DirectRates, the O(N^2) oracle, and FastRates, O(N R log N) with FFT
// convolutions of the kernel's separable form.
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "solvers/model.hpp"

namespace aggkit {

class Rates {
 public:
  virtual ~Rates() = default;
  std::size_t size() const { return size_; }

  // dn/dt at time t.
  virtual void evaluate(double t, std::span<const double> n, std::span<double> dndt) = 0;
  // Rate at which mass leaves through the truncation, ½ Σ_{i+j>N} (i+j) K_ij n_i n_j (0 for cutoff).
  virtual double leak_rate(double t, std::span<const double> n) = 0;
  // Jv = (∂f/∂n)(n) v. The RHS is quadratic in n, so this is exact (no differencing).
  virtual void jacobian_times(double t, std::span<const double> n, std::span<const double> v,
                              std::span<double> Jv) = 0;
  // The part of ∂f/∂n that a preconditioner can invert in O(N): the diagonal, the subdiagonal
  // ∂f_k/∂n_{k-1} (k ≥ 3) and the monomer column ∂f_k/∂n_1 (k ≥ 2) — attachment of monomers, the most
  // frequent collisions. Entry k-1 of each vector belongs to size k (unused entries are 0). O(N R).
  struct MonomerCoupling {
    std::vector<double> diagonal, subdiagonal, monomer_column;
  };
  virtual void jacobian_monomer_coupling(double t, std::span<const double> n, MonomerCoupling& J) = 0;
  virtual std::string describe() const = 0;
  // Rank of the separable kernel form used (0 for the direct path) and its measured max relative error.
  virtual std::size_t kernel_rank() const { return 0; }
  virtual double kernel_relative_error() const { return 0.0; }

  // Adaptive active size range (fast path; the direct path ignores it). With negligible levels ν_k set,
  // sizes beyond the last one with |n_k| > ν_k take no part in collisions, and the FFTs are sized to the
  // sizes that do (solvers/rates_fast.cpp). Empty: every size with n_k ≠ 0 takes part.
  virtual void set_negligible_levels(std::vector<double> levels) { (void)levels; }
  // What the active range saved over the right-hand sides evaluated so far.
  struct ActiveRangeStatistics {
    std::size_t final_size = 0;   // active range of the last state evaluated
    double mean_size = 0.0;       // mean over the states evaluated
    double fft_work_fraction = 1.0;  // Σ L log L of the FFT lengths used / the same at full range
    long states = 0;              // distinct states prepared (right-hand sides and Jacobians share them)
  };
  virtual ActiveRangeStatistics active_range_statistics() const { return {size_, double(size_), 1.0, 0}; }

 protected:
  explicit Rates(std::size_t N) : size_(N) {}
  std::size_t size_;
};

enum class RatesPath { fast, direct };
RatesPath rates_path_from_name(const std::string& name);  // throws InputError
std::string to_string(RatesPath p);

// The direct O(N^2) evaluation; stores the kernel matrix when N is small enough (≤ 8192).
std::unique_ptr<Rates> make_direct_rates(const AggregationModel& model);
// The fast path. For kernels without an exact factorisation, `lowrank_tolerance` is the relative
// entry error of the form used by the right-hand side, and `jacobian_tolerance` (if larger) that of a
// cheaper lower-rank form used for J·v, which only steers Newton's method.
std::unique_ptr<Rates> make_fast_rates(const AggregationModel& model, double lowrank_tolerance = 1e-12,
                                       double jacobian_tolerance = 0.0);
// The rates on the model's discretisation (solvers/discretisation.hpp): the sectional rates on a graded grid
// (whatever the path), else the path's. The dense Jacobian and the leak gradient are the discretisation's.
std::unique_ptr<Rates> make_rates(const AggregationModel& model, RatesPath path,
                                  double lowrank_tolerance = 1e-12, double jacobian_tolerance = 0.0);

}  // namespace aggkit

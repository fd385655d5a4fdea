#pragma once
// The pair table of the sectional rates on a graded grid (solvers/rates_sectional.cpp): every unordered pair
// (i ≤ j) of size classes with its collision weight w_ij and the stencil its aggregate x_i + x_j lands on,
// built once per discretisation and shared by its rates objects and its dense Jacobian.
//
// Storage: runs of pairs whose stencils start a fixed number of pivots past the larger partner j, so that a
// run's every share is added to consecutive entries (a vector loop). A run is either part of a row (i fixed, j
// = j0, j0 + 1, ...) or part of a diagonal (i = i0 + k, j = j0 + k). On the geometric part of the grid the
// aggregate of (i, i + l) lands the same number of pivots past i + l for every i, so the near band's diagonals
// are runs hundreds of pairs long, where its rows break into runs of three or four (the offset falls from
// ~log 2 / log r to 0 across a row); the unit-spaced sizes, where x_i + x_j is itself a pivot, are long runs
// along rows. Each run stores w and its shares contiguously, pair by pair.
//
// For a kernel with exact factors (Kernel::exact_factors) the pairs whose aggregate stays inside the larger
// partner's interval are summed through those factors instead (solvers/sectional_far_field.hpp); their runs
// are kept for the dense Jacobian only.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "solvers/model.hpp"
#include "solvers/sectional_far_field.hpp"

namespace aggkit {

class SectionalPairs {
 public:
  static constexpr std::size_t max_classes = 6000;
  static constexpr std::size_t max_stencil = 4;

  // The pairs of the pivots x of model's graded grid (its kernel, truncation and share scheme). Throws
  // InputError (key "grid") for more than max_classes pivots.
  SectionalPairs(const AggregationModel& model, const std::vector<double>& x);
  ~SectionalPairs();

  std::size_t size() const { return x_.size(); }
  // Pairs summed by the far field rather than one by one (0 without exact kernel factors).
  std::size_t far_pairs() const;

  // What accumulate works in: the rates of one run, each class's summed collision rate, and the gains padded
  // by a stencil's width (a run's stencils are as wide as its widest; the unused shares are 0).
  struct Scratch {
    std::vector<double> rate, lost, gain;
    SectionalFarField::Scratch far;
  };
  // out += scale Σ_{i≤j} w_ij (u_i v_j + u_j v_i) V_ij (rates_sectional.cpp gives V_ij): with u = v and
  // scale ½ the right-hand side, with u = N, v the direction and scale 1 the product J v.
  void accumulate(double lambda, std::span<const double> u, std::span<const double> v, std::span<double> out,
                  double scale, Scratch& scratch) const;

  // The mass leaving through N per unit time, Σ_{x_i + x_j > N} (x_i + x_j) w_ij N_i N_j (0 under cutoff), and
  // its gradient ∂/∂N_l.
  double leak_rate(std::span<const double> n) const;
  void leak_gradient(std::span<const double> n, std::span<double> gradient) const;

  // The row-major M×M Jacobian ∂f_k/∂N_l.
  void dense(double lambda, std::span<const double> n, std::span<double> jacobian) const;
  // Its diagonal, subdiagonal (∂f_k/∂N_{k−1}) and monomer column (∂f_k/∂N_1, k ≥ 2; entry 0 unused), each
  // of size M.
  void monomer_coupling(double lambda, std::span<const double> n, std::span<double> diagonal,
                        std::span<double> subdiagonal, std::span<double> monomer_column) const;

 private:
  struct Table;  // the pairs row by row while the runs are built (sectional_pairs.cpp)

  // Pairs (i, j) = (i0 + k·di, j0 + k), k < length, di = 1 along a diagonal and 0 along a row. Pair k's
  // weight is data_[at + k] and its share for pivot j + offset + m is data_[at + (m + 1)·length + k],
  // m < count (count 0: the aggregates leave the grid).
  struct Run {
    std::uint32_t i0, j0, length;
    std::int32_t offset;
    std::uint32_t count;
    bool diagonal;
    std::size_t at;
  };

  void build_far_field(const Table& table, const Kernel::Factors& factors, std::vector<std::size_t>& near_end,
                       std::size_t& near_top);
  std::size_t far_partners(const Table& table, std::size_t j);
  void build_runs(const Table& table, const std::vector<std::size_t>& near_end, std::size_t near_top);
  void add_run(const Table& table, Run& run);
  template <class Add>
  void pair_entries(const Run& run, std::uint32_t k, double lambda, std::span<const double> n, Add&& add) const;

  std::vector<double> x_;
  bool cutoff_;
  // The runs in the order accumulate sums them: along diagonals, along rows, those whose aggregates leave the
  // grid (runs_[leak_begin_, summed_runs_)); then the far field's (runs_[summed_runs_, end)).
  std::vector<Run> runs_;
  std::size_t leak_begin_ = 0, summed_runs_ = 0;
  std::size_t longest_run_ = 0;
  std::vector<double> data_;
  std::unique_ptr<SectionalFarField> far_;  // null: every pair near
};

}  // namespace aggkit

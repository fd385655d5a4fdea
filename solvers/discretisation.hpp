#pragma once
// The discretisation of sizes 1..N that the deterministic solvers work on, one object as PETSc's DM is to
// its solvers: it owns the size classes (their sizes x_i and widths Δ_i), the rates on them with their exact
// Jacobians, the carrying of a state from other classes onto these, and the density output. The solvers
// (CVODE, SNES steady states, stability, Hopf search) ask it and never ask which grid it is.
//
// Two kinds (solvers/size_grid.hpp): the uniform grid, every size 1..N a class of its own, with the direct
// O(N²) and fast O(N R log N) rates (solvers/rates_direct.cpp, solvers/rates_fast.cpp) and matrix-free
// Newton–Krylov; and the graded grid, sizes 1..K one by one and then pivots x_{i+1} ≈ r x_i, with the
// sectional rates of a stored pair table (solvers/rates_sectional.cpp) and dense LU solves.
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "solvers/model.hpp"
#include "solvers/rates.hpp"

namespace aggkit {

class Discretisation {
 public:
  virtual ~Discretisation() = default;

  const AggregationModel& model() const { return model_; }
  std::size_t unknowns() const { return sizes_.size(); }
  const std::vector<double>& sizes() const { return sizes_; }   // x_i (1..N on the uniform grid)
  const std::vector<double>& widths() const { return widths_; } // Δ_i (all 1 on the uniform grid)
  std::string describe() const { return model_.grid.describe(); }

  // The model's initial table n_k (k = 1..len) on these classes (to_grid's shares; padded with zeros).
  std::vector<double> initial_state() const { return to_grid(sizes_, model_.initial); }
  // The rates on these classes; on a graded grid the pair table is shared by every rates object and by the
  // dense Jacobian, built once per discretisation. `path`, the tolerances: the uniform grid's choice
  // (solvers/rates.hpp make_fast_rates); the graded grid has one path.
  virtual std::unique_ptr<Rates> rates(RatesPath path = RatesPath::fast, double lowrank_tolerance = 1e-12,
                                       double jacobian_tolerance = 0.0) const = 0;
  // ∂f/∂n, row-major unknowns()×unknowns(), by the exact bilinear form.
  virtual void dense_jacobian(double t, std::span<const double> n, std::span<double> jacobian) const = 0;
  // ∂(leak rate)/∂n_l (drop; zeros under cutoff).
  virtual void leak_gradient(double t, std::span<const double> n, std::span<double> gradient) const = 0;
  // Whether Newton and shift-invert factor J_F densely (a graded grid: a few hundred to a few thousand
  // unknowns) rather than through matrix-free Krylov solves (the uniform grid, up to 2^16 unknowns).
  virtual bool dense_solves() const = 0;
  // A state on classes of sizes `from` (empty: the integers 1..state.size()) carried onto these classes: a
  // Newton start when N, K or r changed. Where the classes agree the state is kept; beyond the old range the
  // tail is continued by the fit ln f = a + b ln x + c x (solvers/size_grid.hpp regrid).
  virtual std::vector<double> carry(std::span<const double> from, std::span<const double> state) const = 0;

  // The sizes a density output names per row, or empty where the rows are the integers 1..N (the uniform
  // grid: distribution.csv keeps its "k = row number" form there).
  virtual std::vector<double> output_sizes() const = 0;
  // The density per unit size at each class that its number stands for (solvers/size_grid.hpp
  // section_densities; the n_k themselves on the uniform grid).
  std::vector<double> densities(std::span<const double> n) const;

 protected:
  Discretisation(const AggregationModel& model, std::vector<double> sizes);
  AggregationModel model_;
  std::vector<double> sizes_, widths_;
};

// The model's discretisation (its `grid`). Throws InputError for a grid too long for the solvers.
std::unique_ptr<Discretisation> make_discretisation(const AggregationModel& model);
// The graded one (solvers/rates_sectional.cpp); make_discretisation picks it.
std::unique_ptr<Discretisation> make_graded_discretisation(const AggregationModel& model);

}  // namespace aggkit

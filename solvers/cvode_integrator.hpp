#pragma once
// Time integration of the aggregation-shattering system with SUNDIALS CVODE.
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "solvers/model.hpp"
#include "solvers/rates.hpp"

namespace aggkit {

enum class IntegratorMethod {
  bdf_gmres,  // BDF, Newton with matrix-free GMRES (J·v in O(N R log N)) and a preconditioner
  bdf_dense,  // BDF, Newton with the dense analytic Jacobian (small N only)
  adams,      // Adams-Moulton with functional (fixed-point) iteration, for non-stiff runs
};
IntegratorMethod integrator_method_from_name(const std::string& name);  // throws InputError
std::string to_string(IntegratorMethod m);

// Preconditioner for bdf-gmres: P = I - γ M with M a part of the Jacobian solvable in O(N).
enum class Preconditioner {
  none,
  jacobi,   // M = diagonal of J
  monomer,  // M = diagonal + subdiagonal + monomer column (monomer attachment), lower triangular
};
Preconditioner preconditioner_from_name(const std::string& name);  // throws InputError
std::string to_string(Preconditioner p);

struct IntegratorOptions {
  IntegratorMethod method = IntegratorMethod::bdf_gmres;
  RatesPath rates = RatesPath::fast;
  double rtol = 1e-8;
  // Absolute tolerance on n_k is atol / k^atol_exponent. With exponent q the error of M_p, p < q, is
  // bounded by about atol Σ_k k^{p-q}: q = 1 weighs the mass, larger q protects the high moments
  // (M2, M3) that live in the large-size tail.
  double atol = 1e-14;
  double atol_exponent = 1.0;
  Preconditioner preconditioner = Preconditioner::monomer;
  bool project_mass = true;     // cutoff + BDF: project each step onto Σ k n_k = M (exact invariant)
  int krylov_dimension = 0;     // 0: SUNDIALS default (5)
  double linear_tolerance_factor = 0.05;  // GMRES stops at this factor of the Newton tolerance (CVodeSetEpsLin)
  long max_steps = 10'000'000;
  double lowrank_tolerance = 1e-12;
  // Relative entry error of the cheaper kernel form used for J·v (approximated kernels only; Newton's
  // method needs only an approximate Jacobian). 0 uses the right-hand side's form.
  double jacobian_tolerance = 1e-4;
  std::size_t dense_limit = 4000;  // bdf_dense refuses larger N
  // Called after every internal step with the time reached (for progress reports); may be empty.
  std::function<void(double t)> progress;
  void validate() const;           // throws InputError on non-positive or non-finite tolerances
};

struct IntegratorStatistics {
  long steps = 0, rhs_evaluations = 0, linear_iterations = 0, jacobian_vector_products = 0;
  long jacobian_evaluations = 0, preconditioner_setups = 0, preconditioner_solves = 0;
  long error_test_failures = 0, nonlinear_failures = 0, linear_convergence_failures = 0;
  double wall_seconds = 0.0;
  std::size_t kernel_rank = 0;            // rank of the separable kernel form (fast path)
  double kernel_relative_error = 0.0;     // its measured max relative entry error
  std::size_t negative_densities = 0;     // entries < 0 in the last output (round-off), before clipping
  double most_negative_density = 0.0;
};

// Called at each output time with the densities (sizes 1..N) and the mass leaked so far (drop).
using OutputCallback = std::function<void(double t, std::span<const double> n, double leaked_mass)>;

// Integrates from t = 0 to each of `output_times` (increasing, > 0; t = 0 itself is reported if listed).
// Throws std::runtime_error with CVODE's flag and the time reached if the integrator fails.
IntegratorStatistics integrate(const AggregationModel& model, std::span<const double> output_times,
                               const IntegratorOptions& options, const OutputCallback& on_output);

}  // namespace aggkit

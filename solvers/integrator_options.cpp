// The options of the CVODE integrator, bound to IntegratorOptions (analysis/option_rows.hpp): the scene's
// engine "cvode" reads them, IntegratorOptions::validate() checks their ranges.
#include "analysis/option_rows.hpp"
#include "solvers/cvode_integrator.hpp"

namespace aggkit {

const OptionRows<IntegratorOptions>& integrator_option_rows() {
  using O = IntegratorOptions;
  using B = Bind<O>;
  static const OptionRows<O> rows{{
      B::named("method", &O::method,
               std::vector{IntegratorMethod::bdf_gmres, IntegratorMethod::bdf_dense, IntegratorMethod::adams,
                           IntegratorMethod::erk, IntegratorMethod::automatic},
               "BDF with matrix-free GMRES, BDF with a dense Jacobian (small N), Adams, explicit Runge-Kutta "
               "(erk_table), or auto: erk while its steps are bounded by accuracy, bdf-gmres once stability bounds them"),
      B::number("rtol", &O::rtol, open(0.0, 1.0), "relative tolerance"),
      B::number("atol", &O::atol, at_least(0.0), "absolute tolerance of n_1 (atol_k = atol / k^atol_exponent); 0 = default",
                "rtol/100"),
      B::number("atol_exponent", &O::atol_exponent, closed(0.0, 6.0), "q of atol_k = atol / k^q (3 controls M0..M3)"),
      B::number("atol_floor", &O::atol_floor, at_least(0.0),
                "lower bound of atol_k relative to the largest initial density (0: 1e-10 rtol)"),
      B::number("atol_mass", &O::atol_mass, right_open(0.0, 1.0),
                "upper bound of x_k atol_k, the mass a class's tolerance stands for, relative to the initial mass; over "
                "the floor (0: none)"),
      B::named("rhs", &O::rates, std::vector{RatesPath::fast, RatesPath::direct},
               "right-hand side: FFT/low-rank O(N R log N), or the direct O(N^2) sums"),
      B::number("lowrank_tolerance", &O::lowrank_tolerance, right_open(0.0, 0.1),
                "relative error of the low-rank kernel (0: default)", "10 rtol within [1e-12, 1e-5]"),
      B::number("jacobian_tolerance", &O::jacobian_tolerance, right_open(0.0, 0.1),
                "low-rank tolerance of the Jacobian-vector products"),
      B::number("negligible_fraction", &O::negligible_fraction, closed(0.0, 0.1),
                "sizes beyond the last with |n_k| > this fraction of atol_k take no part (adaptive active range; 0: off)"),
      B::named("preconditioner", &O::preconditioner, std::vector{Preconditioner::monomer, Preconditioner::jacobi, Preconditioner::none},
               "bdf-gmres preconditioner"),
      B::named("erk_table", &O::erk_table,
               std::vector{ErkTable::dormand_prince_5, ErkTable::verner_6, ErkTable::fehlberg_8},
               "the explicit Runge-Kutta pair of erk and auto (ARKODE's tables)"),
      B::integer("krylov", &O::krylov_dimension, closed(0, 500), "Krylov subspace dimension (0: CVODE's default 5)"),
      B::number("linear_tolerance_factor", &O::linear_tolerance_factor, left_open(0.0, 1.0),
                "GMRES stops at this factor of the Newton tolerance (CVodeSetEpsLin)"),
      B::integer("max_steps", &O::max_steps, at_least(1), "most internal steps"),
      B::flag("project_mass", &O::project_mass, "project steps and outputs onto the conserved mass"),
  }};
  return rows;
}

}  // namespace aggkit

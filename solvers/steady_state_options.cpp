#include "solvers/steady_state_options.hpp"

#include "solvers/petsc_options.hpp"

namespace aggkit {

const OptionRows<SteadyStateOptions>& steady_state_option_rows() {
  using O = SteadyStateOptions;
  using B = Bind<O>;
  static const OptionRows<O> rows{{
      B::number("tolerance", &O::relative_tolerance, left_open(0.0, 1.0),
                "relative residual ||F|| / ||F(n(0))|| at which Newton stops"),
      B::number("balance_tolerance", &O::balance_tolerance, left_open(0.0, 1.0),
                "and the root's own balance: ||F|| over the free rows / ||(df_k/dn_k) n_k|| at which Newton stops"),
      B::integer("max_newton_iterations", &O::max_newton_iterations, closed(1, 10000), "most Newton iterations"),
      B::named("rhs", &O::rates, std::vector{RatesPath::fast, RatesPath::direct},
               "right-hand side: FFT/low-rank, or the direct O(N^2) sums"),
      B::number("start_time", &O::start_time, greater_than(0.0), "the initial guess is the CVODE solution at this time"),
      B::flag("precondition", &O::precondition, "precondition GMRES (false: plain GMRES, for comparison only)"),
      B::custom("petsc_options", "a string of PETSc options \"-name value -flag ...\"",
                "PETSc options for the SNES, its KSP and PC, applied after the above (e.g. \"-snes_rtol 1e-12 "
                "-ksp_type bcgs\"); the command line's (aggkit run ... -- OPTIONS) come after these",
                "", [](const O& o) { return nlohmann::json(o.petsc_options); },
                [](O& o, const nlohmann::json& value, const std::string& key) {
                  if (!value.is_string()) throw InputError(key, option_text(value), "a string of PETSc options \"-name value -flag ...\"");
                  o.petsc_options = value.get<std::string>();
                  check_petsc_options(o.petsc_options, key);  // bad input before any output
                }),
  }};
  return rows;
}

// The settings a scene does not give (the library's own tuning): rows too, so that validate() checks every
// bound from one declaration, though no engine table lists them.
const OptionRows<SteadyStateOptions>& steady_state_tuning_rows() {
  using O = SteadyStateOptions;
  using B = Bind<O>;
  static const OptionRows<O> rows{{
      B::number("start_rtol", &O::start_rtol, greater_than(0.0), "rtol of the CVODE start"),
      B::number("linear_tolerance", &O::linear_tolerance, greater_than(0.0),
                "relative GMRES tolerance when eisenstat_walker is false"),
      B::integer("krylov_restart", &O::krylov_restart, at_least(1), "GMRES restart"),
      B::integer("max_krylov_iterations", &O::max_krylov_iterations, at_least(1), "most GMRES iterations per Newton step"),
      B::integer("start_retries", &O::start_retries, at_least(0), "CVODE start retries, each 10x longer"),
  }};
  return rows;
}

void SteadyStateOptions::validate() const {
  steady_state_option_rows().check(*this);
  steady_state_tuning_rows().check(*this);
}

}  // namespace aggkit

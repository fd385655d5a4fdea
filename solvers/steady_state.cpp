#include "solvers/steady_state.hpp"

#include <petscsnes.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <optional>


#include "analysis/input_error.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/mass_constrained_system.hpp"
#include "solvers/petsc_options.hpp"
#include "solvers/petsc_session.hpp"
#include "solvers/petsc_shell.hpp"

namespace aggkit {

namespace {

struct NewtonContext {
  MassConstrainedSystem* system = nullptr;
  std::vector<double> dense;      // graded grid: J_F, row-major (PETSc's dense matrices are column-major)
  ShellOperator op;
  std::vector<double> history;
  double target = 0.0;            // the relative residual asked for
  double balance = 0.0;           // SteadyStateOptions::balance_tolerance
  bool first_forcing = false;     // set the first Eisenstat–Walker forcing term from the start's residual
};

PetscErrorCode form_function(SNES, Vec x, Vec f, void* data) {
  auto* c = static_cast<NewtonContext*>(data);
  const std::size_t N = c->system->size();
  const PetscScalar* xx = nullptr;
  PetscScalar* ff = nullptr;
  VecGetArrayRead(x, &xx);
  VecGetArray(f, &ff);
  PetscErrorCode code = 0;
  try {
    c->system->residual({xx, N}, {ff, N});
  } catch (...) {
    code = PETSC_ERR_LIB;
  }
  VecRestoreArray(f, &ff);
  VecRestoreArrayRead(x, &xx);
  return code;
}

PetscErrorCode form_jacobian(SNES, Vec x, Mat J, Mat, void* data) {
  auto* c = static_cast<NewtonContext*>(data);
  const PetscScalar* xx = nullptr;
  VecGetArrayRead(x, &xx);
  PetscErrorCode code = 0;
  try {
    const std::size_t N = c->system->size();
    if (c->system->dense()) {
      c->dense.resize(N * N);
      c->system->dense_jacobian({xx, N}, c->dense);
      PetscScalar* a = nullptr;
      MatDenseGetArrayWrite(J, &a);
      for (std::size_t row = 0; row < N; ++row)
        for (std::size_t column = 0; column < N; ++column) a[column * N + row] = c->dense[row * N + column];
      MatDenseRestoreArrayWrite(J, &a);
      MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY);
      MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY);
    }
    c->system->set_state({xx, c->system->size()});
  } catch (...) {
    code = PETSC_ERR_LIB;
  }
  VecRestoreArrayRead(x, &xx);
  return code;
}

// PETSc's default test (the absolute one on the scaled norm set above, divergence, iteration limits), and a
// root it accepts must also balance its own rates: the free rows' residual ≤ balance_tolerance ·
// balance_scale(n), and the mass row ≤ balance_tolerance · M. Near n(0) the default test is the stricter one;
// at small densities (small λ) the balance test is, and without it Newton stopped at its start whenever the
// rates there were below the absolute level (brownian a = 0.59, λ = 7.4e-11: 0 iterations, the root of the
// previous λ accepted).
PetscErrorCode converged_balance(SNES snes, PetscInt iteration, PetscReal xnorm, PetscReal step, PetscReal fnorm,
                                 SNESConvergedReason* reason, void* data) {
  PetscErrorCode code = SNESConvergedDefault(snes, iteration, xnorm, step, fnorm, reason, nullptr);
  if (code || *reason != SNES_CONVERGED_FNORM_ABS) return code;
  auto* c = static_cast<NewtonContext*>(data);
  Vec x = nullptr, f = nullptr;
  SNESGetSolution(snes, &x);
  SNESGetFunction(snes, &f, nullptr, nullptr);
  const PetscScalar* xx = nullptr;
  const PetscScalar* ff = nullptr;
  VecGetArrayRead(x, &xx);
  VecGetArrayRead(f, &ff);
  try {
    MassConstrainedSystem& system = *c->system;
    const std::size_t row = system.mass_row();
    double free = 0.0;
    for (std::size_t k = 0; k < system.size(); ++k)
      if (k != row) free += ff[k] * ff[k];
    const bool balanced = std::sqrt(free) <= c->balance * system.balance_scale({xx, system.size()}) &&
                          std::abs(ff[row]) <= c->balance * system.mass();
    if (!balanced) *reason = SNES_CONVERGED_ITERATING;
  } catch (...) {
    code = PETSC_ERR_LIB;
  }
  VecRestoreArrayRead(f, &ff);
  VecRestoreArrayRead(x, &xx);
  return code;
}

PetscErrorCode record_residual(SNES snes, PetscInt iteration, PetscReal norm, void* data) {
  auto* c = static_cast<NewtonContext*>(data);
  const double relative = norm / c->system->residual_scale();
  c->history.push_back(relative);
  // Eisenstat–Walker's first forcing term (0.3 by default) suits a far start. From a start already near
  // the root (the coarse-to-fine start: within 4 orders of the target), Newton converges quadratically and
  // a first linear solve to about target / residual reaches the target in one step instead of three loose
  // ones (each with residuals and a line search at full size). Bounded to [1e-4, 0.3]: never looser than
  // the default, never oversolved.
  if (iteration == 0 && c->first_forcing && relative <= 1e4 * c->target) {
    const double eta = std::clamp(0.5 * c->target / relative, 1e-4, 0.3);
    return SNESKSPSetParametersEW(snes, PETSC_DEFAULT, eta, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT,
                                  PETSC_DEFAULT);
  }
  return 0;
}

// One SNES solve from `guess`; fills the result (n, convergence, counts, history).
void newton(MassConstrainedSystem& system, const SteadyStateOptions& options, std::span<const double> guess,
            SteadyStateResult& result) {
  const PetscInt N = PetscInt(system.size());
  NewtonContext context;
  context.system = &system;
  context.op.system = &system;
  context.target = options.relative_tolerance;
  context.balance = options.balance_tolerance;
  context.first_forcing = options.eisenstat_walker;
  SNES snes = nullptr;
  Vec x = nullptr, r = nullptr;
  Mat J = nullptr;
  std::optional<PetscOptionDatabase> database;  // outlives the SNES that reads it (destroyed in cleanup)
  auto cleanup = [&] {
    if (snes) SNESDestroy(&snes);
    if (J) MatDestroy(&J);
    if (x) VecDestroy(&x);
    if (r) VecDestroy(&r);
  };
  try {
    check_petsc(VecCreateSeq(PETSC_COMM_SELF, N, &x), "VecCreateSeq");
    check_petsc(VecDuplicate(x, &r), "VecDuplicate");
    PetscScalar* xx = nullptr;
    check_petsc(VecGetArray(x, &xx), "VecGetArray");
    std::copy(guess.begin(), guess.end(), xx);
    VecRestoreArray(x, &xx);
    if (system.dense()) {
      // Graded grid: a few hundred to a few thousand unknowns, so Newton's linear solves are one dense LU
      // each (O(M^3/3), ~10 ms at M = 500) instead of GMRES, whose iterations grow with the far sections'
      // stiffness.
      check_petsc(MatCreateSeqDense(PETSC_COMM_SELF, N, N, nullptr, &J), "MatCreateSeqDense");
    } else {
      J = make_shell_matrix(context.op);
    }
    check_petsc(SNESCreate(PETSC_COMM_SELF, &snes), "SNESCreate");
    // The user's PETSc options (scene, then command line): a database of this SNES and its KSP, PC and line
    // search, read by SNESSetFromOptions after aggkit's settings.
    const std::string user_options = options.petsc_options + " " + options.command_line_petsc_options;
    if (user_options.find_first_not_of(' ') != std::string::npos) database.emplace(user_options, "petsc_options");
    if (user_options.find("-snes_ksp_ew") != std::string::npos) context.first_forcing = false;  // theirs rules
    check_petsc(SNESSetType(snes, SNESNEWTONLS), "SNESSetType");
    check_petsc(SNESSetFunction(snes, r, form_function, &context), "SNESSetFunction");
    check_petsc(SNESSetJacobian(snes, J, J, form_jacobian, &context), "SNESSetJacobian");
    SNESLineSearch line_search = nullptr;
    check_petsc(SNESGetLineSearch(snes, &line_search), "SNESGetLineSearch");
    check_petsc(SNESLineSearchSetType(line_search, SNESLINESEARCHBT), "SNESLineSearchSetType");
    // Absolute test on the scaled norm; no relative or step-size test (they would stop early).
    check_petsc(SNESSetTolerances(snes, options.relative_tolerance * system.residual_scale(), 0.0, 0.0,
                                  options.max_newton_iterations, 100 * options.max_newton_iterations),
                "SNESSetTolerances");
    check_petsc(SNESSetConvergenceTest(snes, converged_balance, &context, nullptr), "SNESSetConvergenceTest");
    check_petsc(SNESMonitorSet(snes, record_residual, &context, nullptr), "SNESMonitorSet");
    KSP ksp = nullptr;
    check_petsc(SNESGetKSP(snes, &ksp), "SNESGetKSP");
    check_petsc(KSPSetType(ksp, KSPGMRES), "KSPSetType");
    check_petsc(KSPGMRESSetRestart(ksp, options.krylov_restart), "KSPGMRESSetRestart");
    check_petsc(KSPSetPCSide(ksp, PC_RIGHT), "KSPSetPCSide");  // GMRES then minimises the true residual
    check_petsc(KSPSetTolerances(ksp, options.linear_tolerance, 1e-300, PETSC_DEFAULT, options.max_krylov_iterations),
                "KSPSetTolerances");
    PC pc = nullptr;
    check_petsc(KSPGetPC(ksp, &pc), "KSPGetPC");
    if (system.dense()) {
      check_petsc(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
      check_petsc(PCSetType(pc, PCLU), "PCSetType");
      context.first_forcing = false;
    } else {
      set_shell_preconditioner(pc, context.op, options.precondition);
      if (options.eisenstat_walker) check_petsc(SNESKSPSetUseEW(snes, PETSC_TRUE), "SNESKSPSetUseEW");
    }
    if (database) {
      check_petsc(use_options_database(snes, database->get()), "PetscObjectSetOptions");
      check_petsc(SNESSetFromOptions(snes), "SNESSetFromOptions (petsc_options)");
    }
    check_petsc(SNESSolve(snes, nullptr, x), "SNESSolve");
    if (database) result.unused_petsc_options = database->unused();
    SNESConvergedReason reason;
    SNESGetConvergedReason(snes, &reason);
    PetscInt iterations = 0, linear = 0;
    SNESGetIterationNumber(snes, &iterations);
    SNESGetLinearSolveIterations(snes, &linear);
    result.newton_iterations += int(iterations);
    result.krylov_iterations += long(linear);
    result.converged = reason > 0;
    if (reason <= 0) result.note += std::string("SNES stopped: ") + SNESConvergedReasons[reason] + "; ";
    const PetscScalar* solution = nullptr;
    VecGetArrayRead(x, &solution);
    result.n.assign(solution, solution + N);
    VecRestoreArrayRead(x, &solution);
  } catch (...) {
    cleanup();
    throw;
  }
  cleanup();
  result.residual_history.insert(result.residual_history.end(), context.history.begin(), context.history.end());
}

// A steady state must be a density: negative entries beyond round-off mean Newton found another root
// of the quadratic system.
double most_negative(std::span<const double> n) {
  double largest = 0.0, lowest = 0.0;
  for (double x : n) {
    largest = std::max(largest, std::abs(x));
    lowest = std::min(lowest, x);
  }
  return largest > 0.0 ? lowest / largest : 0.0;
}
constexpr double negative_density_limit = -1e-8;

constexpr double negative_mass_limit = 1e-6;

std::vector<double> cvode_start(const AggregationModel& model, double time, double rtol) {
  IntegratorOptions integrator;
  integrator.rtol = rtol;
  std::vector<double> state;
  const double times[] = {time};
  integrate(model, times, integrator, [&](double, std::span<const double> n, double) { state.assign(n.begin(), n.end()); });
  return state;
}

double seconds_since(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// The converged steady state at N / 4 for the coarse-to-fine start, or nullopt where it does not apply or
// did not converge to a density. It serves the matrix-free path; a discretisation that solves densely (a
// graded grid, a few thousand unknowns at most) does without.
std::optional<std::vector<double>> coarse_start(const AggregationModel& model, const SteadyStateOptions& options,
                                                bool dense_solves) {
  const std::size_t N = model.size, Nc = N / 4;
  if (options.coarse_start_above == 0 || N <= options.coarse_start_above || dense_solves) return std::nullopt;
  for (std::size_t k = Nc; k < model.initial.size(); ++k)
    if (model.initial[k] != 0.0) return std::nullopt;  // the initial state (its mass) must fit the coarse sizes
  AggregationModel coarse = model;
  coarse.size = Nc;
  coarse.initial.resize(Nc);
  SteadyStateResult r = solve_steady_state(coarse, options);
  if (!r.converged) return std::nullopt;
  return std::move(r.n);
}

}  // namespace

double negative_mass_fraction(std::span<const double> n, std::span<const double> sizes) {
  double total = 0.0, negative = 0.0;
  for (std::size_t k = 0; k < n.size(); ++k) {
    total += sizes[k] * std::abs(n[k]);
    if (n[k] < 0.0) negative -= sizes[k] * n[k];
  }
  return total > 0.0 ? negative / total : 0.0;
}

SteadyStateResult solve_steady_state(const AggregationModel& model, const SteadyStateOptions& options,
                                     std::span<const double> initial_guess) {
  options.validate();
  const auto started = std::chrono::steady_clock::now();
  MassConstrainedSystem system(model, options.rates, options.lowrank_tolerance);
  if (!initial_guess.empty() && initial_guess.size() != system.size())
    throw InputError("initial_guess", std::to_string(initial_guess.size()) + " entries",
                     "exactly model.size = " + std::to_string(system.size()) + " entries");
  for (double x : initial_guess)
    if (!std::isfinite(x)) throw InputError("initial_guess", format_value(x), "finite densities");
  ensure_petsc_initialized();

  SteadyStateResult result;
  result.setup_seconds = seconds_since(started);
  std::vector<double> guess(initial_guess.begin(), initial_guess.end());
  if (guess.empty()) {
    const auto coarse_started = std::chrono::steady_clock::now();
    if (auto coarse = coarse_start(model, options, system.dense())) {
      result.coarse_size = coarse->size();
      guess = system.discretisation().carry({}, *coarse);
    }
    result.start_seconds = seconds_since(coarse_started);
  }
  const std::vector<double>& sizes = system.sizes();
  double start_time = options.start_time;
  const int attempts = 1 + options.start_retries + (result.coarse_size > 0 ? 1 : 0);
  for (int attempt = 0; attempt < attempts; ++attempt) {
    if (guess.empty()) {
      const auto cvode_started = std::chrono::steady_clock::now();
      guess = cvode_start(model, start_time, options.start_rtol);
      result.start_seconds += seconds_since(cvode_started);
      result.start_time = start_time;
      start_time *= 10.0;
    } else {
      result.start_time = 0.0;
    }
    newton(system, options, guess, result);
    result.most_negative_density = most_negative(result.n);
    result.negative_mass_fraction = negative_mass_fraction(result.n, sizes);
    if (result.converged && result.most_negative_density >= negative_density_limit &&
        result.negative_mass_fraction <= negative_mass_limit)
      break;
    if (result.converged) {
      result.converged = false;
      result.note += "converged to a root with negative densities (min n / max n = " +
                     format_value(result.most_negative_density) + ", negative mass fraction " +
                     format_value(result.negative_mass_fraction) + "); ";
    }
    if (attempt + 1 < attempts)
      result.note += (result.start_time == 0.0 && result.coarse_size > 0 && attempt == 0 ? "from the coarse start: " : "") +
                     std::string("retrying from a CVODE run to t = ") + format_value(start_time) + "; ";
    guess.clear();
  }
  std::vector<double> F(system.size());
  system.residual(result.n, F);
  double norm = 0.0;
  for (double x : F) norm += x * x;
  result.relative_residual = std::sqrt(norm) / system.residual_scale();
  result.leak_rate = system.leak_rate(result.n) / system.mass();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

namespace {

// Continuation along a parameter p: model_at(p) builds the model, the guess is the secant extrapolation.
std::vector<SteadyStateResult> continuation(std::span<const double> parameters,
                                            const std::function<AggregationModel(double)>& model_at,
                                            const SteadyStateOptions& options) {
  std::vector<SteadyStateResult> results;
  std::vector<double> guess;
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    if (i >= 1 && results[i - 1].converged) {
      guess = results[i - 1].n;
      if (i >= 2 && results[i - 2].converged && parameters[i - 1] != parameters[i - 2]) {
        const double s = (parameters[i] - parameters[i - 1]) / (parameters[i - 1] - parameters[i - 2]);
        for (std::size_t k = 0; k < guess.size(); ++k) guess[k] += s * (guess[k] - results[i - 2].n[k]);
      }
    } else {
      guess.clear();
    }
    results.push_back(solve_steady_state(model_at(parameters[i]), options, guess));
    // An extrapolated guess that failed gets a second chance from CVODE.
    if (!results.back().converged && !guess.empty()) results.back() = solve_steady_state(model_at(parameters[i]), options);
  }
  return results;
}

}  // namespace

std::vector<SteadyStateResult> continue_in_lambda(const AggregationModel& base, std::span<const double> lambdas,
                                                  const SteadyStateOptions& options) {
  return continuation(lambdas, [&](double lambda) {
    AggregationModel model = base;
    model.lambda = ShatteringRate::constant(lambda);
    return model;
  }, options);
}

std::vector<SteadyStateResult> continue_in_a(const AggregationModel& base, std::span<const double> a_values,
                                             const SteadyStateOptions& options) {
  return continuation(a_values, [&](double a) {
    AggregationModel model = base;
    model.kernel = Kernel::brownian(a);
    return model;
  }, options);
}

}  // namespace aggkit

#include "solvers/stability.hpp"

// GCC 12 reports -Wuse-after-free in Eigen's aligned_free, inlined into Spectra's
// UpperHessenbergEigen::doComputeEigenvectors (a temporary vector resized, then destroyed: each buffer is
// freed once): a false positive of the warning new in GCC 12, in library headers we do not own. It is
// silenced for these headers only; the warning is located in Eigen's Memory.h, so the pragma wraps the
// includes (the first inclusion of Eigen in this file).
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuse-after-free"
#endif
#include <Eigen/Dense>
#include <Spectra/GenEigsRealShiftSolver.h>
#include <Spectra/GenEigsSolver.h>
#include <Spectra/MatOp/DenseGenRealShiftSolve.h>
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12
#pragma GCC diagnostic pop
#endif
#include <petscksp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "analysis/input_error.hpp"
#include "solvers/mass_constrained_system.hpp"
#include "solvers/mass_shell.hpp"
#include "solvers/petsc_session.hpp"
#include "solvers/petsc_shell.hpp"

namespace aggkit {

namespace {

using Complex = std::complex<double>;

void sort_rightmost(std::vector<Complex>& values) {
  std::sort(values.begin(), values.end(), [](Complex x, Complex y) {
    return x.real() != y.real() ? x.real() > y.real() : x.imag() > y.imag();
  });
}

// All eigenvalues of A.
std::vector<Complex> dense_spectrum(const Discretisation& grid, std::span<const double> n,
                                    std::size_t m) {
  const Eigen::MatrixXd A = mass_shell_jacobian(grid, n, m);
  Eigen::EigenSolver<Eigen::MatrixXd> solver(A, false);
  if (solver.info() != Eigen::Success) throw std::runtime_error("dense eigenvalue solver failed (Eigen QR)");
  std::vector<Complex> values(solver.eigenvalues().begin(), solver.eigenvalues().end());
  return values;
}

// (A - σI)^{-1} applied by GMRES on (J_F - σB) v = (b, 0): the operator Spectra iterates on.
class ShiftInvertOperator {
 public:
  using Scalar = double;
  ShiftInvertOperator(MassConstrainedSystem& system, const StabilityOptions& options)
      : system_(system), m_(system.mass_row()) {
    op_.system = &system;
    op_.shift = options.shift;
    const PetscInt N = PetscInt(system.size());
    check_petsc(VecCreateSeq(PETSC_COMM_SELF, N, &rhs_), "VecCreateSeq");
    check_petsc(VecDuplicate(rhs_, &solution_), "VecDuplicate");
    matrix_ = make_shell_matrix(op_);
    check_petsc(KSPCreate(PETSC_COMM_SELF, &ksp_), "KSPCreate");
    check_petsc(KSPSetOperators(ksp_, matrix_, matrix_), "KSPSetOperators");
    check_petsc(KSPSetType(ksp_, KSPGMRES), "KSPSetType");
    check_petsc(KSPGMRESSetRestart(ksp_, options.krylov_restart), "KSPGMRESSetRestart");
    check_petsc(KSPSetPCSide(ksp_, PC_RIGHT), "KSPSetPCSide");
    check_petsc(KSPSetTolerances(ksp_, options.linear_tolerance, 1e-300, PETSC_DEFAULT, 5000), "KSPSetTolerances");
    PC pc = nullptr;
    check_petsc(KSPGetPC(ksp_, &pc), "KSPGetPC");
    set_shell_preconditioner(pc, op_, true);
  }
  ~ShiftInvertOperator() {
    KSPDestroy(&ksp_);
    MatDestroy(&matrix_);
    VecDestroy(&rhs_);
    VecDestroy(&solution_);
  }
  ShiftInvertOperator(const ShiftInvertOperator&) = delete;
  ShiftInvertOperator& operator=(const ShiftInvertOperator&) = delete;

  Eigen::Index rows() const { return Eigen::Index(m_); }
  Eigen::Index cols() const { return Eigen::Index(m_); }
  void perform_op(const double* x, double* y) const {
    PetscScalar* b = nullptr;
    VecGetArray(rhs_, &b);
    std::copy(x, x + m_, b);
    std::fill(b + m_, b + system_.size(), 0.0);
    VecRestoreArray(rhs_, &b);
    check_petsc(KSPSolve(ksp_, rhs_, solution_), "KSPSolve (shift-invert)");
    KSPConvergedReason reason;
    KSPGetConvergedReason(ksp_, &reason);
    if (reason == KSP_DIVERGED_BREAKDOWN) {
      // GMRES breakdown close to round-off (the 1e-12 target is near what the operator's own round-off
      // allows): accept the iterate if its residual is small enough for the Ritz values (1e-8 relative
      // perturbs the eigenvalues of (A - σI)^{-1} by about as much, far below locate_hopf's 1e-3).
      PetscReal residual = 0, norm_b = 0;
      KSPGetResidualNorm(ksp_, &residual);
      VecNorm(rhs_, NORM_2, &norm_b);
      if (residual <= 1e-8 * norm_b) reason = KSP_CONVERGED_RTOL;
    }
    if (reason < 0)
      throw std::runtime_error(std::string("shift-invert GMRES did not converge: ") + KSPConvergedReasons[reason]);
    PetscInt iterations = 0;
    KSPGetIterationNumber(ksp_, &iterations);
    iterations_ += iterations;
    ++applications_;
    const PetscScalar* v = nullptr;
    VecGetArrayRead(solution_, &v);
    std::copy(v, v + m_, y);
    VecRestoreArrayRead(solution_, &v);
  }
  long iterations() const { return iterations_; }
  int applications() const { return applications_; }

 private:
  MassConstrainedSystem& system_;
  std::size_t m_;
  ShellOperator op_;
  Vec rhs_ = nullptr, solution_ = nullptr;
  Mat matrix_ = nullptr;
  KSP ksp_ = nullptr;
  mutable long iterations_ = 0;
  mutable int applications_ = 0;
};

// The eigenvalues of A nearest σ by Arnoldi on (A - σI)^{-1}, applied through one dense LU of A - σI
// (Spectra's DenseGenRealShiftSolve, Eigen's partial-pivoting LU): O(m^3/3) once, then O(m^2) per
// application. For the graded grid's few hundred to few thousand unknowns this replaces both the full
// dense QR (O(10 m^3)) and the matrix-free GMRES solves (hundreds of iterations each).
std::vector<Complex> dense_shift_invert_spectrum(const Discretisation& grid, std::span<const double> n,
                                                 std::size_t m,
                                                 const StabilityOptions& options, int wanted, StabilityResult& result) {
  const Eigen::MatrixXd A = mass_shell_jacobian(grid, n, m);
  Spectra::DenseGenRealShiftSolve<double> op(A);
  const Eigen::Index size = Eigen::Index(m);
  const Eigen::Index nev = std::min<Eigen::Index>(std::max(wanted, options.krylov_eigenvalues), size - 2);
  const Eigen::Index ncv = std::min<Eigen::Index>(std::max<Eigen::Index>(2 * nev + 1, 20), size);
  Spectra::GenEigsRealShiftSolver<Spectra::DenseGenRealShiftSolve<double>> eigs(op, nev, ncv, options.shift);
  eigs.init();
  const Eigen::Index converged = eigs.compute(Spectra::SortRule::LargestMagn, 1000, options.eigen_tolerance);
  result.operator_applications = int(eigs.num_operations());
  if (eigs.info() != Spectra::CompInfo::Successful || converged < 1)
    throw std::runtime_error("Arnoldi (Spectra) did not converge on the dense shift-invert operator");
  const auto values = eigs.eigenvalues();  // already μ = σ + 1/ν
  return {values.begin(), values.end()};
}

std::vector<Complex> krylov_spectrum(MassConstrainedSystem& system, std::span<const double> n,
                                     const StabilityOptions& options, int wanted, StabilityResult& result) {
  ensure_petsc_initialized();
  system.set_state(n);
  ShiftInvertOperator op(system, options);
  const Eigen::Index m = op.rows();
  const Eigen::Index nev = std::min<Eigen::Index>(std::max(wanted, options.krylov_eigenvalues), m - 2);
  const Eigen::Index ncv = std::min<Eigen::Index>(std::max<Eigen::Index>(2 * nev + 1, 20), m);
  Spectra::GenEigsSolver<ShiftInvertOperator> eigs(op, nev, ncv);
  eigs.init();
  eigs.compute(Spectra::SortRule::LargestMagn, 1000, options.eigen_tolerance);
  result.linear_iterations = op.iterations();
  result.operator_applications = op.applications();
  if (eigs.info() != Spectra::CompInfo::Successful)
    throw std::runtime_error("Arnoldi (Spectra) did not converge on the shift-invert operator");
  std::vector<Complex> values;
  for (const Complex& nu : eigs.eigenvalues())
    if (nu != Complex(0.0)) values.push_back(options.shift + 1.0 / nu);  // ν = 1/(μ - σ)
  return values;
}

}  // namespace

// A = J_{<m,<m} + J_{<m,m} t^T (the Jacobian on the mass shell, t_k = -x_k/x_m) from the discretisation's
// dense Jacobian (on a graded grid from its pair table, built once per analysis).
Eigen::MatrixXd mass_shell_jacobian(const Discretisation& grid, std::span<const double> n, std::size_t m) {
  const std::size_t N = grid.unknowns();
  const std::vector<double>& x = grid.sizes();
  std::vector<double> jacobian(N * N);
  grid.dense_jacobian(0.0, n, jacobian);
  Eigen::MatrixXd A(m, m);
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t k = 0; k < m; ++k) A(i, k) = jacobian[i * N + k] - jacobian[i * N + m] * x[k] / x[m];
  return A;
}

std::complex<double> rightmost_complex_pair(std::span<const std::complex<double>> eigenvalues) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Complex best(nan, nan);
  for (const Complex& mu : eigenvalues) {
    // A pair: Im clearly nonzero relative to |μ| (real eigenvalues come out with Im = 0 exactly or ~ε).
    if (mu.imag() <= 1e-10 * std::abs(mu)) continue;
    if (std::isnan(best.real()) || mu.real() > best.real()) best = mu;
  }
  return best;
}

StabilityResult analyse_stability(const AggregationModel& model, std::span<const double> steady_state, int count) {
  return analyse_stability(model, steady_state, count, StabilityOptions{});
}

StabilityResult analyse_stability(const AggregationModel& model, std::span<const double> steady_state, int count,
                                  const StabilityOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  if (count < 1) throw InputError("count", std::to_string(count), "at least one eigenvalue");
  const std::size_t unknowns = model.unknowns();
  if (steady_state.size() != unknowns)
    throw InputError("steady_state", std::to_string(steady_state.size()) + " entries",
                     "exactly one per size class (" + std::to_string(unknowns) + ")");
  for (double x : steady_state)
    if (!std::isfinite(x)) throw InputError("steady_state", format_value(x), "finite densities");
  if (!std::isfinite(options.shift)) throw InputError("shift", format_value(options.shift), "a finite shift");
  MassConstrainedSystem system(model, RatesPath::fast, options.lowrank_tolerance);
  const std::size_t m = system.mass_row();
  const bool factored = system.dense();
  const bool dense = options.method == SpectrumMethod::dense ||
                     (options.method == SpectrumMethod::automatic && unknowns <= (factored ? 200 : options.dense_limit)) ||
                     m < 8;
  // Where the discretisation solves densely (a graded grid) the Krylov path is the dense shift-invert one.
  StabilityResult result;
  result.method = dense ? "dense" : factored ? "dense-shift-invert" : "krylov";
  std::vector<Complex> values = dense      ? dense_spectrum(system.discretisation(), steady_state, m)
                                : factored ? dense_shift_invert_spectrum(system.discretisation(), steady_state, m, options, count, result)
                                           : krylov_spectrum(system, steady_state, options, count, result);
  sort_rightmost(values);
  if (values.size() > std::size_t(count)) {
    // Keep a conjugate pair together.
    std::size_t keep = std::size_t(count);
    if (values[keep - 1].imag() != 0.0 && keep < values.size() && values[keep] == std::conj(values[keep - 1])) ++keep;
    values.resize(keep);
  }
  result.rightmost = std::move(values);
  result.stable = result.rightmost.empty() || result.rightmost.front().real() < 0.0;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace aggkit

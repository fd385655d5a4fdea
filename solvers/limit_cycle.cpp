#include "solvers/limit_cycle.hpp"

#include <petscksp.h>
#include <Eigen/Core>
#include <Spectra/GenEigsSolver.h>

#include <algorithm>
#include <chrono>
#include <deque>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "analysis/input_error.hpp"
#include "solvers/cvode_integrator.hpp"
#include "solvers/discretisation.hpp"
#include "solvers/mass_constrained_system.hpp"
#include "solvers/petsc_database.hpp"
#include "solvers/petsc_session.hpp"

namespace aggkit {

void LimitCycleOptions::validate() const {
  if (!(rtol >= 1e-13 && rtol <= 1e-4)) throw InputError("rtol", format_value(rtol), "a relative tolerance in [1e-13, 1e-4]");
  if (!(tolerance > 0.0 && tolerance < 1.0)) throw InputError("tolerance", format_value(tolerance), "a number in (0, 1)");
  if (max_newton_iterations < 1 || max_newton_iterations > 200)
    throw InputError("max_newton_iterations", std::to_string(max_newton_iterations), "an integer in [1, 200]");
  if (!(linear_tolerance > 0.0 && linear_tolerance < 1.0))
    throw InputError("linear_tolerance", format_value(linear_tolerance), "a number in (0, 1)");
  if (max_krylov_iterations < 1 || max_krylov_iterations > 2000)
    throw InputError("max_krylov_iterations", std::to_string(max_krylov_iterations), "an integer in [1, 2000]");
  if (floquet_count < 0 || floquet_count > 50)
    throw InputError("floquet_count", std::to_string(floquet_count), "an integer in [0, 50]");
  if (orbit_samples < 2 || orbit_samples > 1'000'000)
    throw InputError("orbit_samples", std::to_string(orbit_samples), "an integer in [2, 1000000]");
}

namespace {

double seconds_since(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// The period map φ_T and the right-hand side f on the model's classes.
class Flow {
 public:
  Flow(const AggregationModel& model, double rtol)
      : model_(model), grid_(make_discretisation(model)), rates_(grid_->rates()) {
    options_.rtol = rtol;
    options_.stability_limit_detection = false;  // a period map smooth to the tolerance (IntegratorOptions)
  }
  std::size_t size() const { return grid_->unknowns(); }
  const std::vector<double>& sizes() const { return grid_->sizes(); }
  long maps() const { return maps_; }

  // φ_T(x0), or the states at `times` (increasing, > 0) from x0 at t = 0.
  std::vector<std::vector<double>> states(std::span<const double> x0, std::span<const double> times) {
    IntegratorRestart start;
    start.densities.assign(x0.begin(), x0.end());
    std::vector<std::vector<double>> out;
    integrate(model_, times, options_, [&](double, std::span<const double> n, double) { out.emplace_back(n.begin(), n.end()); },
              &start);
    ++maps_;
    return out;
  }
  std::vector<double> map(std::span<const double> x0, double T) {
    const double times[] = {T};
    return std::move(states(x0, times).front());
  }
  std::vector<double> rhs(std::span<const double> n) const {
    std::vector<double> f(n.size());
    rates_->evaluate(0.0, n, f);
    return f;
  }

 private:
  AggregationModel model_;
  std::unique_ptr<Discretisation> grid_;
  std::unique_ptr<Rates> rates_;
  IntegratorOptions options_;
  long maps_ = 0;
};

// The shooting equations of limit_cycle.hpp in scaled unknowns z = (x0 / d, T / T_ref), rows scaled by s.
class Shooting {
 public:
  Shooting(Flow& flow, const AggregationModel& model, std::span<const double> start, double period)
      : flow_(flow), x_ref_(start.begin(), start.end()), T_ref_(period), M_(flow.size()) {
    MassConstrainedSystem system(model);  // the mass row and the model's mass
    m_ = system.mass_row();
    mass_ = system.mass();
    const double top = *std::max_element(x_ref_.begin(), x_ref_.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
    s_.resize(M_);
    // Relative errors where a density is above 1e-8 of the largest: a finer scale makes the forward differences
    // of φ_T noise in the far tail, whose densities CVODE resolves only to its absolute tolerance.
    for (std::size_t k = 0; k < M_; ++k) s_[k] = std::abs(x_ref_[k]) + 1e-8 * std::abs(top);
    // The unknowns move on the scale d_k = min(s_k, 2 |x_ref,k|): below the floor an entry moves in proportion
    // to its own size, since the far tail (densities ~1e-16 of the largest, at sizes whose cube is ~1e18, which
    // carry much of M3) would otherwise take updates of the floor's size and leave M3 off by percents while the
    // residual stays small. The forward differences of φ_T perturb on the same scale, so that the Jacobian
    // models the step Newton takes (with differences on s and steps on d, Newton converged only linearly and
    // stalled at scaled residuals of 1e-4..1e-2 on cycles far below the curve).
    d_.resize(M_);
    for (std::size_t k = 0; k < M_; ++k) d_[k] = std::min(s_[k], 2.0 * std::abs(x_ref_[k]));
    f_ref_ = flow_.rhs(x_ref_);
    phase_norm_ = 0.0;
    for (std::size_t k = 0; k < M_; ++k) phase_norm_ += std::abs(f_ref_[k]) * s_[k];
    if (!(phase_norm_ > 0.0)) throw std::runtime_error("the start is a steady state (f = 0): no phase condition");
  }

  std::size_t unknowns() const { return M_ + 1; }

  // Moves to (x0, T) and returns F there; where the integration fails (a state CVODE cannot follow) it throws
  // and stays where it was.
  std::vector<double> residual_at(const std::vector<double>& x0, double T) {
    std::vector<double> phi = flow_.map(x0, T);
    x0_ = x0;
    T_ = T;
    phi_ = std::move(phi);
    f_phi_ = flow_.rhs(phi_);
    std::vector<double> F(M_ + 1);
    const std::vector<double>& x = flow_.sizes();
    double mass = 0.0, phase = 0.0;
    for (std::size_t k = 0; k < M_; ++k) {
      F[k] = (phi_[k] - x0_[k]) / s_[k];
      if (k <= m_) mass += x[k] * x0_[k];
      phase += f_ref_[k] * (x0_[k] - x_ref_[k]);
    }
    F[m_] = (mass - mass_) / mass_;
    for (std::size_t k = m_ + 1; k < M_; ++k) F[k] = x0_[k] / s_[k];  // pinned rows (cutoff): n_N = 0
    F[M_] = phase / phase_norm_;
    return F;
  }

  // out = J z by a forward difference of φ_T along d∘z (rows scaled by s).
  void apply(const double* z, double* out) {
    const std::vector<double>& x = flow_.sizes();
    double largest = 0.0;
    for (std::size_t k = 0; k < M_; ++k) largest = std::max(largest, std::abs(d_[k] * z[k]) / s_[k]);
    std::vector<double> dphi(M_, 0.0);
    if (largest > 0.0) {
      const double eps = 1e-5 / largest;
      std::vector<double> moved(x0_);
      for (std::size_t k = 0; k < M_; ++k) moved[k] += eps * d_[k] * z[k];
      const std::vector<double> phi = flow_.map(moved, T_);
      for (std::size_t k = 0; k < M_; ++k) dphi[k] = (phi[k] - phi_[k]) / eps;
    }
    const double dT = T_ref_ * z[M_];
    double mass = 0.0, phase = 0.0;
    for (std::size_t k = 0; k < M_; ++k) {
      const double dx = d_[k] * z[k];
      out[k] = (dphi[k] - dx + f_phi_[k] * dT) / s_[k];
      if (k <= m_) mass += x[k] * dx;
      phase += f_ref_[k] * dx;
    }
    out[m_] = mass / mass_;
    for (std::size_t k = m_ + 1; k < M_; ++k) out[k] = z[k];
    out[M_] = phase / phase_norm_;
  }

  // (x, T) moved by the scaled step dz times `fraction`.
  std::pair<std::vector<double>, double> stepped(std::vector<double> x, double T, const std::vector<double>& dz,
                                                 double fraction) const {
    for (std::size_t k = 0; k < M_; ++k) x[k] += fraction * d_[k] * dz[k];
    return {std::move(x), T + fraction * T_ref_ * dz[M_]};
  }

  const std::vector<double>& x0() const { return x0_; }
  double period() const { return T_; }
  const std::vector<double>& scale() const { return s_; }
  std::size_t mass_row() const { return m_; }
  const std::vector<double>& sizes() const { return flow_.sizes(); }

 private:
  Flow& flow_;
  std::vector<double> x_ref_, f_ref_, s_, d_, x0_, phi_, f_phi_;
  double T_ref_, T_ = 0.0, mass_ = 0.0, phase_norm_ = 0.0;
  std::size_t M_, m_ = 0;
};

PetscErrorCode shooting_mult(Mat A, Vec x, Vec y) {
  void* ctx = nullptr;
  MatShellGetContext(A, &ctx);
  auto* shooting = static_cast<Shooting*>(ctx);
  const PetscScalar* xx = nullptr;
  PetscScalar* yy = nullptr;
  VecGetArrayRead(x, &xx);
  VecGetArray(y, &yy);
  PetscErrorCode code = 0;
  try {
    shooting->apply(xx, yy);
  } catch (...) {
    code = PETSC_ERR_LIB;
  }
  VecRestoreArray(y, &yy);
  VecRestoreArrayRead(x, &xx);
  return code;
}

double max_norm(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

// Solves J dz = -F by unpreconditioned GMRES (PETSc KSP on a MatShell); returns the iterations.
long krylov_step(Shooting& shooting, const std::vector<double>& F, std::vector<double>& dz, const LimitCycleOptions& options) {
  const PetscInt n = PetscInt(shooting.unknowns());
  Mat A = nullptr;
  KSP ksp = nullptr;
  Vec b = nullptr, x = nullptr;
  check_petsc(MatCreateShell(PETSC_COMM_SELF, n, n, n, n, &shooting, &A), "MatCreateShell");
  check_petsc(MatShellSetOperation(A, MATOP_MULT, (void (*)(void))shooting_mult), "MatShellSetOperation");
  check_petsc(VecCreateSeq(PETSC_COMM_SELF, n, &b), "VecCreateSeq");
  check_petsc(VecDuplicate(b, &x), "VecDuplicate");
  PetscScalar* bb = nullptr;
  VecGetArray(b, &bb);
  for (PetscInt k = 0; k < n; ++k) bb[k] = -F[std::size_t(k)];
  VecRestoreArray(b, &bb);
  check_petsc(KSPCreate(PETSC_COMM_SELF, &ksp), "KSPCreate");
  check_petsc(KSPSetOperators(ksp, A, A), "KSPSetOperators");
  check_petsc(KSPSetType(ksp, KSPGMRES), "KSPSetType");
  check_petsc(KSPGMRESSetRestart(ksp, options.max_krylov_iterations), "KSPGMRESSetRestart");
  PC pc = nullptr;
  check_petsc(KSPGetPC(ksp, &pc), "KSPGetPC");
  check_petsc(PCSetType(pc, PCNONE), "PCSetType");
  check_petsc(KSPSetTolerances(ksp, options.linear_tolerance, PETSC_DEFAULT, PETSC_DEFAULT, options.max_krylov_iterations),
              "KSPSetTolerances");
  const PetscErrorCode solved = KSPSolve(ksp, b, x);
  PetscInt iterations = 0;
  KSPGetIterationNumber(ksp, &iterations);
  const PetscScalar* xx = nullptr;
  VecGetArrayRead(x, &xx);
  dz.assign(xx, xx + n);
  VecRestoreArrayRead(x, &xx);
  KSPDestroy(&ksp);
  VecDestroy(&x);
  VecDestroy(&b);
  MatDestroy(&A);
  check_petsc(solved, "KSPSolve (shooting Newton step)");
  return long(iterations);
}

// Where the largest entry of the residual sits: a class (its size), the mass row or the phase row.
std::string where_largest(const Shooting& shooting, const std::vector<double>& F) {
  std::size_t k = 0;
  for (std::size_t i = 1; i < F.size(); ++i)
    if (std::abs(F[i]) > std::abs(F[k])) k = i;
  if (k + 1 == F.size()) return " (in the phase condition)";
  if (k == shooting.mass_row()) return " (in the mass row)";
  return " (at size " + format_value(shooting.sizes()[k]) + ")";
}

// Newton on the shooting equations with a halving line search on max|F|.
void newton(Shooting& shooting, std::vector<double> x0, double T, const LimitCycleOptions& options, LimitCycle& cycle) {
  std::vector<double> F = shooting.residual_at(x0, T);
  double norm = max_norm(F);
  for (int iteration = 0; iteration < options.max_newton_iterations && norm > options.tolerance; ++iteration) {
    std::vector<double> dz;
    cycle.krylov_iterations += krylov_step(shooting, F, dz, options);
    ++cycle.newton_iterations;
    const std::vector<double> from = shooting.x0();
    const double from_T = shooting.period();
    bool improved = false;
    for (double fraction = 1.0; fraction >= 1.0 / 16; fraction /= 2) {
      auto [x, t] = shooting.stepped(from, from_T, dz, fraction);
      if (!(t > 0.0)) continue;
      std::vector<double> trial;
      try {
        trial = shooting.residual_at(x, t);
      } catch (const std::runtime_error&) {
        continue;  // a step too long for the integrator (a state it cannot follow): a shorter one
      }
      if (max_norm(trial) < norm) {
        F = std::move(trial);
        norm = max_norm(F);
        improved = true;
        break;
      }
    }
    if (!improved) {
      cycle.note = "Newton stalled at scaled residual " + format_value(norm) + where_largest(shooting, F);
      break;
    }
  }
  cycle.residual = norm;
  cycle.converged = norm <= options.tolerance;
  if (!cycle.converged && cycle.note.empty())
    cycle.note = "Newton did not reach the tolerance in " + std::to_string(options.max_newton_iterations) + " iterations (scaled residual " + format_value(norm) + ")";
}

// The monodromy matrix ∂φ_T/∂x0 at the cycle, on mass-keeping perturbations, in the scaled unknowns: the
// operator Spectra's Arnoldi iterates on (a forward difference of φ_T per application).
class Monodromy {
 public:
  using Scalar = double;
  Monodromy(Flow& flow, const std::vector<double>& x0, double T, const std::vector<double>& s, std::size_t mass_row)
      : flow_(flow), x0_(x0), s_(s), T_(T), phi_(flow.map(x0, T)), m_(mass_row) {
    const std::vector<double>& x = flow_.sizes();
    for (std::size_t k = 0; k <= m_; ++k) mass_ += x[k] * x0_[k];
  }
  Eigen::Index rows() const { return Eigen::Index(x0_.size()); }
  Eigen::Index cols() const { return rows(); }

  void perform_op(const double* z, double* out) const {
    const std::size_t M = x0_.size();
    std::vector<double> dx(M);
    for (std::size_t k = 0; k < M; ++k) dx[k] = s_[k] * z[k];
    keep_mass(dx);
    double largest = 0.0;
    for (std::size_t k = 0; k < M; ++k) largest = std::max(largest, std::abs(dx[k]) / s_[k]);
    if (largest == 0.0) {
      std::fill(out, out + M, 0.0);
      return;
    }
    const double eps = 1e-5 / largest;
    std::vector<double> moved(x0_);
    for (std::size_t k = 0; k < M; ++k) moved[k] += eps * dx[k];
    const std::vector<double> phi = flow_.map(moved, T_);
    std::vector<double> dphi(M);
    for (std::size_t k = 0; k < M; ++k) dphi[k] = (phi[k] - phi_[k]) / eps;
    keep_mass(dphi);
    for (std::size_t k = 0; k < M; ++k) out[k] = dphi[k] / s_[k];
  }

 private:
  // Removes the mass a perturbation carries along x0 itself (Q v = v − x0 (w·v)/(w·x0)): the flow keeps mass,
  // so the mass direction's multiplier 1 becomes 0 and the rest are unchanged.
  void keep_mass(std::vector<double>& v) const {
    const std::vector<double>& x = flow_.sizes();
    double carried = 0.0;
    for (std::size_t k = 0; k <= m_; ++k) carried += x[k] * v[k];
    for (std::size_t k = 0; k < v.size(); ++k) v[k] -= x0_[k] * carried / mass_;
  }

  Flow& flow_;
  std::vector<double> x0_, s_;
  double T_;
  std::vector<double> phi_;
  std::size_t m_;
  double mass_ = 0.0;
};

// The nontrivial Floquet multipliers: Arnoldi for the largest |μ|, less the phase direction's trivial μ = 1
// (the eigenvector most nearly parallel to f(x0)).
void floquet_multipliers(Flow& flow, const Shooting& shooting, const LimitCycleOptions& options, LimitCycle& cycle) {
  if (options.floquet_count == 0) return;
  Monodromy op(flow, cycle.state, cycle.period, shooting.scale(), shooting.mass_row());
  const Eigen::Index n = op.rows();
  const Eigen::Index nev = std::min<Eigen::Index>(options.floquet_count + 1, n - 2);
  const Eigen::Index ncv = std::min<Eigen::Index>(std::max<Eigen::Index>(2 * nev + 1, 16), n);
  Spectra::GenEigsSolver<Monodromy> eigs(op, nev, ncv);
  eigs.init();
  eigs.compute(Spectra::SortRule::LargestMagn, 200, 1e-4);
  cycle.floquet_converged = eigs.info() == Spectra::CompInfo::Successful;
  if (!cycle.floquet_converged) {
    cycle.note += "Floquet multipliers: Arnoldi did not converge; ";
    return;
  }
  const Eigen::VectorXcd values = eigs.eigenvalues();
  const Eigen::MatrixXcd vectors = eigs.eigenvectors();
  std::vector<double> f = flow.rhs(cycle.state);
  Eigen::VectorXd phase(n);
  for (Eigen::Index k = 0; k < n; ++k) phase[k] = f[std::size_t(k)] / shooting.scale()[std::size_t(k)];
  phase.normalize();
  Eigen::Index trivial = 0;
  double best = -1.0;
  for (Eigen::Index j = 0; j < values.size(); ++j) {
    const double overlap = std::abs(vectors.col(j).dot(phase.cast<std::complex<double>>())) / vectors.col(j).norm();
    if (overlap > best) best = overlap, trivial = j;
  }
  for (Eigen::Index j = 0; j < values.size(); ++j)
    if (j != trivial) cycle.floquet.push_back(values[j]);
  std::sort(cycle.floquet.begin(), cycle.floquet.end(), [](auto a, auto b) { return std::abs(a) > std::abs(b); });
  if (std::abs(values[trivial] - 1.0) > 1e-2)
    cycle.note += "the phase direction's multiplier is " + format_value(std::abs(values[trivial])) + ", not 1; ";
  cycle.stable = cycle.converged && (cycle.floquet.empty() || std::abs(cycle.floquet.front()) < 1.0);
}

// One period of the orbit: M0..M3 at orbit_samples + 1 times from 0 to T, and M0's range.
void orbit(Flow& flow, const LimitCycleOptions& options, LimitCycle& cycle) {
  const std::size_t samples = options.orbit_samples;
  std::vector<double> times(samples);
  for (std::size_t j = 1; j <= samples; ++j) times[j - 1] = cycle.period * double(j) / double(samples);
  std::vector<std::vector<double>> states = flow.states(cycle.state, times);
  states.insert(states.begin(), cycle.state);
  cycle.orbit_time.assign(1, 0.0);
  cycle.orbit_time.insert(cycle.orbit_time.end(), times.begin(), times.end());
  const std::vector<double>& x = flow.sizes();
  for (const std::vector<double>& n : states) {
    std::array<double, 4> m{0, 0, 0, 0};
    for (std::size_t k = 0; k < n.size(); ++k)
      for (int p = 0; p < 4; ++p) m[std::size_t(p)] += n[k] * std::pow(x[k], p);
    cycle.orbit_moments.push_back(m);
  }
  cycle.m0_min = cycle.m0_max = cycle.orbit_moments.front()[0];
  for (const auto& m : cycle.orbit_moments) cycle.m0_min = std::min(cycle.m0_min, m[0]), cycle.m0_max = std::max(cycle.m0_max, m[0]);
}

void check_start(const AggregationModel& model, std::span<const double> start, double period_guess) {
  if (!model.lambda.is_constant())
    throw InputError("lambda", model.lambda.describe(), "a constant shattering rate for a periodic orbit");
  if (start.size() != model.unknowns())
    throw InputError("start", std::to_string(start.size()) + " entries",
                     "one density per size class (" + std::to_string(model.unknowns()) + ")");
  for (double x : start)
    if (!std::isfinite(x)) throw InputError("start", format_value(x), "finite densities");
  if (!(period_guess > 0.0) || !std::isfinite(period_guess))
    throw InputError("period_guess", format_value(period_guess), "a finite period > 0");
}

}  // namespace

LimitCycle find_limit_cycle(const AggregationModel& model, std::span<const double> start, double period_guess,
                            const LimitCycleOptions& options) {
  options.validate();
  model.validate(period_guess);
  check_start(model, start, period_guess);
  ensure_petsc_initialized();
  const auto started = std::chrono::steady_clock::now();
  LimitCycle cycle;
  Flow flow(model, options.rtol);
  cycle.sizes = flow.sizes();
  try {
    Shooting shooting(flow, model, start, period_guess);
    newton(shooting, std::vector<double>(start.begin(), start.end()), period_guess, options, cycle);
    cycle.state = shooting.x0();
    cycle.period = shooting.period();
    if (cycle.converged) {
      orbit(flow, options, cycle);
      floquet_multipliers(flow, shooting, options, cycle);
    }
  } catch (const std::runtime_error& e) {
    cycle.converged = false;
    cycle.note += e.what();
  }
  cycle.period_maps = flow.maps();
  cycle.seconds = seconds_since(started);
  return cycle;
}

IntegratorOptions cycle_run_options(double rtol, long max_steps, const RunTolerance& tolerance) {
  IntegratorOptions options;
  options.rtol = rtol;
  if (max_steps < 0) throw InputError("max_steps", std::to_string(max_steps), "a step count >= 1, or 0 for the default");
  if (max_steps > 0) options.max_steps = max_steps;
  options.atol = tolerance.atol;  // their ranges are checked by integrate (IntegratorOptions::validate)
  options.atol_floor = tolerance.atol_floor;
  options.atol_mass = tolerance.atol_mass;
  options.stability_limit_detection = false;  // a return map smooth to the tolerance (IntegratorOptions)
  options.project_outputs = false;            // the states handed on are the integrator's own (IntegratorOptions)
  return options;
}

std::optional<CycleStart> cycle_start_from_run(const AggregationModel& model, double t_end, double spacing, double rtol,
                                               std::span<const double> from, long max_steps, const RunTolerance& tolerance,
                                               GridEnd* grid_end) {
  if (!(t_end > 0.0) || !std::isfinite(t_end)) throw InputError("t_end", format_value(t_end), "a finite time > 0");
  if (!(spacing > 0.0 && spacing < t_end)) throw InputError("spacing", format_value(spacing), "a spacing in (0, t_end)");
  std::vector<double> times;
  for (double t = spacing; t <= t_end * (1 + 1e-12); t += spacing) times.push_back(t);
  IntegratorOptions options = cycle_run_options(rtol, max_steps, tolerance);
  // M0 over the second half, and only the latest states: a run of 12/Re μ at 50 outputs per period can have
  // 10^5 outputs of several hundred classes, and the start is the state at the last crossing, within the
  // last period of an oscillating run.
  constexpr std::size_t kept = 4000;
  std::vector<double> m0;
  CycleStart start;
  std::deque<std::vector<double>> states;
  const auto sum = [](std::span<const double> n) {
    double total = 0.0;
    for (double v : n) total += v;
    return total;
  };
  options.on_step = [&](double t, std::span<const double> n) {
    if (t < 0.5 * t_end || t > t_end) return;
    start.step_times.push_back(t);
    start.step_m0.push_back(sum(n));
  };
  IntegratorRestart restart;
  if (!from.empty()) {
    check_start(model, from, t_end);
    restart.densities.assign(from.begin(), from.end());
  }
  GridEnd local;
  GridEnd& end = grid_end ? *grid_end : local;  // filled as the run goes: a run that throws leaves what it saw
  end = GridEnd{};
  const std::vector<double> pivots = model.pivots();
  const std::size_t top = std::size_t(std::upper_bound(pivots.begin(), pivots.end(), 0.5 * double(model.size)) - pivots.begin());
  integrate(model, times, options, [&](double t, std::span<const double> n, double leaked_so_far) {
    end.leaked_mass = leaked_so_far;
    double held = 0.0;
    for (std::size_t k = top; k < n.size(); ++k) held += pivots[k] * n[k];
    end.top_octave_mass = std::max(end.top_octave_mass, held);
    if (t < 0.5 * t_end) return;
    m0.push_back(sum(n));
    states.emplace_back(n.begin(), n.end());
    if (states.size() > kept) states.pop_front();
  }, from.empty() ? nullptr : &restart);
  const std::size_t first = times.size() - m0.size();
  double mean = 0.0;
  for (double v : m0) mean += v;
  mean /= double(m0.size());
  std::vector<double> crossings;
  std::size_t last = 0;
  for (std::size_t i = 1; i < m0.size(); ++i)
    if (m0[i - 1] < mean && m0[i] >= mean) {
      const double f = (mean - m0[i - 1]) / (m0[i] - m0[i - 1]);
      crossings.push_back(times[first + i - 1] + f * spacing);
      last = i;
    }
  const std::size_t oldest = m0.size() - states.size();  // m0 index of states.front()
  if (crossings.size() < 3 || last < oldest) return std::nullopt;
  const std::size_t use = std::min<std::size_t>(crossings.size(), 6);
  start.crossings = int(crossings.size());
  start.period = (crossings.back() - crossings[crossings.size() - use]) / double(use - 1);
  start.state = states[last - oldest];
  start.times.assign(times.begin() + std::ptrdiff_t(first), times.end());
  start.m0 = std::move(m0);
  return start;
}

}  // namespace aggkit

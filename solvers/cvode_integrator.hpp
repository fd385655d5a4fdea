#pragma once
// Time integration of the aggregation-shattering system with SUNDIALS CVODE [Hindmarsh2005, Gardner2022].
#include <cstddef>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/option_rows.hpp"
#include "solvers/model.hpp"
#include "solvers/rates.hpp"

namespace aggkit {

enum class IntegratorMethod {
  bdf_gmres,  // BDF, Newton with matrix-free GMRES (J·v in O(N R log N)) and a preconditioner
  bdf_dense,  // BDF, Newton with the dense analytic Jacobian (small N only)
  adams,      // Adams-Moulton with functional (fixed-point) iteration, for non-stiff runs
  erk,        // explicit Runge-Kutta (ARKODE ERKStep, erk_table), for non-stiff runs at tight tolerances
  automatic,  // "auto": erk while its steps are bounded by accuracy, bdf-gmres once stability bounds them
};
IntegratorMethod integrator_method_from_name(const std::string& name);  // throws InputError
std::string to_string(IntegratorMethod m);

// The embedded explicit Runge-Kutta pair of the erk method (ARKODE's tables).
enum class ErkTable {
  dormand_prince_5,  // Dormand-Prince 5(4), 7 stages
  verner_6,          // Verner 6(5), 8 stages
  fehlberg_8,        // Fehlberg 8(7), 13 stages
};
std::string to_string(ErkTable t);

// Preconditioner for bdf-gmres: P = I - γ M with M a part of the Jacobian solvable in O(N).
enum class Preconditioner {
  none,
  jacobi,   // M = diagonal of J
  monomer,  // M = diagonal + subdiagonal + monomer column (monomer attachment), lower triangular
};
Preconditioner preconditioner_from_name(const std::string& name);  // throws InputError
std::string to_string(Preconditioner p);

// Defaults chosen by the work-precision study (bench/results/log/cvode-work-precision.md): at rtol 1e-6 the moments M0, M2, M3
// are within ~3e-7 of a tight reference for the ballistic and constant kernels with shattering.
// What integrate() throws where a run needs more than IntegratorOptions::max_steps internal steps: a budget
// reached, not a solver failure (callers that set a budget tell the two apart).
struct StepLimitReached : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct IntegratorOptions {
  IntegratorMethod method = IntegratorMethod::bdf_gmres;
  RatesPath rates = RatesPath::fast;
  double rtol = 1e-6;
  // Absolute tolerance on n_k is atol / k^atol_exponent. With exponent q the error of M_p, p < q, is
  // bounded by about atol Σ_k k^{p-q}: q = 3 protects M0..M3, whose large-size tail a mass-weighted
  // (q = 1) tolerance leaves uncontrolled (M3 errors of 1e-2 at rtol 1e-10 were seen with q = 1).
  // atol = 0 (default) chooses 1e-2 rtol.
  double atol = 0.0;
  double atol_exponent = 3.0;
  // Lower bound of atol_k, relative to the largest initial density. The FFT gain is accurate to about
  // 1e-16 of the largest densities; below that, tolerance-level junk in the far tail evolves
  // non-smoothly and a smaller atol_k makes CVODE chase it with tiny steps (30x more steps were seen
  // for the ballistic kernel at λ = 1 without the floor; bench/results/log/cvode-stress.md, stress runs). 0 (default)
  // chooses 1e-10 rtol, i.e. 1e-16 at rtol 1e-6. The floor does not bound M3 by itself (Σ k³ · floor
  // over N sizes is ~N^4/4 · floor): the moments stay proportional to rtol because sizes beyond the
  // distribution's support stay exactly empty (the mass projection leaves them alone). A start that
  // fills every size with sub-tolerance values (e.g. 1e-30) defeats the tilted convolution, and FFT
  // round-off below the floor then sets M3 to ~1e-5 whatever rtol (N = 32768; bench/results/log/cvode-tolerance-proportionality.md).
  double atol_floor = 0.0;
  double effective_atol_floor() const { return atol_floor > 0.0 ? atol_floor : 1e-10 * rtol; }
  // Upper bound of the mass a class's absolute tolerance stands for, relative to the initial mass M:
  // atol_k <= atol_mass · M / x_k, over the floor (0, default: no bound). On a graded grid reaching N = 2^40 the
  // floor lets a far-tail class of size x ~ 1e12 hold junk worth 1e12 · floor of mass; in a relaxation burst
  // the Newton corrections spread such junk of both signs over the empty tail, the leak through N (drop)
  // then swings by ~1e-4 of M a burst, and the mass projection hands that to n_1, which went to -5e-4
  // (brownian a = 0.75, λ = 1e-6, atol 1e-14, floor 1e-14: bench/results/RESULTS.md, "The monomer's
  // tolerance and the far tail's mass"). With the bound 1e-15 the same run kept its mass to 1.2e-5.
  double atol_mass = 0.0;
  // Adaptive active size range (fast right-hand side): sizes beyond the last one with |n_k| above
  // negligible_fraction · atol_k take no part in collisions, and the FFTs shrink to the sizes that do
  // (solvers/rates_fast.cpp). What that leaves out is of order the fraction times atol_k, far below the
  // tolerance; the range grows as the distribution's tail rises above that level. 0: every size with
  // n_k ≠ 0 takes part (the full range once the tail has filled it). On the README example the fractions
  // 1e-2 … 1e-9 all leave M0, M2, M3 within 4e-8 of the full range's at t = 1, 10, 100 (rtol 1e-6; the
  // default is tested in tests/solvers/test_active_range.cpp);
  // the step count varies with the fraction by chance of the step-size controller (674 at 1e-2, 837 at
  // 1e-3 and 1e-4, 680 at 1e-6, 669 at 1e-9; 680 with the full range), so the default is the safe end.
  double negligible_fraction = 1e-6;
  Preconditioner preconditioner = Preconditioner::monomer;
  // For erk and auto. Dormand-Prince: on the ballistic kernel (λ = 0.01, N = 2000, rtol 1e-6, t = 100) it took
  // 645 steps (4000 right-hand sides) where Verner 6(5) took 4300 steps and Fehlberg 8(7) 2260 (32600
  // right-hand sides): past t = 20 the Fehlberg pair's steps stayed 4x below what stability allows.
  ErkTable erk_table = ErkTable::dormand_prince_5;
  int krylov_dimension = 0;     // 0: SUNDIALS default (5)
  double linear_tolerance_factor = 0.05;  // GMRES stops at this factor of the Newton tolerance (CVodeSetEpsLin)
  // Project each output, and each BDF step while atol ≥ 1e-10, onto Σ k n_k + L = M (the exact
  // invariant; L the leaked mass), so that mass is conserved to round-off. Without it the mass drifts by
  // the accumulated Newton/GMRES residual, which grows with λ: at rtol 1e-6 over t = 10^4 it reached 4e-7
  // (λ = 0.01), 3e-4 (λ = 1) and 8e-3 (λ = 10), with M0 off by 0.8 % (bench/results/log/cvode-stress.md, stress runs).
  // The correction goes only to the sizes in the relative-tolerance regime (solvers/cvode_integrator.cpp,
  // project_onto_mass_shell), so it leaves the moments' errors proportional to rtol. Below atol 1e-10
  // projecting the steps made CVODE take 4-5x more steps, so only the outputs are projected there.
  bool project_mass = true;
  // With project_mass, also each output (off: the steps only, where they are projected). The cycle computations
  // turn it off (cycle_run_options): below atol 1e-10 their steps are not projected, and projecting the outputs
  // put the leaked mass's integration error on the smallest resolved sizes, where the quiescent phase of a
  // relaxation cycle holds n_1 ~ 1e-9 — L, held to rtol · M, took up junk of 6e-7 to 2.5e-5 in a burst while the
  // distribution held its mass (brownian a = 0.7, λ = 1e-8 on the scan's grid; a = 0.75, λ = 1e-6 on graded K = 8,
  // r = 1.6, whose true leak is 1e-11), and the states the columns hand on went negative in n_1 (bench/results/RESULTS.md,
  // "The leaked mass's junk and the projected outputs").
  bool project_outputs = true;
  // CVODE's BDF stability limit detection [Hindmarsh2005] (CVodeSetStabLimDet): at orders 3–5 BDF is not
  // A-stable, and near a stable focus the step settles on the boundary of the order's stability region
  // whatever the tolerance. Off, the ballistic kernel at λ = 0.1 (N = 5000, cutoff, rtol 1e-6) took a constant
  // step 0.076 from its steady state on: 13 332 steps to t = 1000; on, 473. Its order changes depend on the
  // step history, so runs from nearby starts can differ at the tolerance's level: the cycle computations
  // (cycle_run_options: return maps, their extrapolation, shooting, the scan's columns) turn it off.
  bool stability_limit_detection = true;
  long max_steps = 10'000'000;
  // Max relative entry error of the low-rank kernel form (kernels without an exact factorisation);
  // 0 chooses 10 rtol within [1e-12, 1e-5] (1e-12 about the attainable floor). The factorisation meets a
  // requested tolerance with ~10-100x to spare (requested 1e-8: 1.1e-10 measured), and a kernel error moves the
  // moments by ~1e-2 of itself: on the ballistic kernel (λ = 0.01, N = 2000, rtol 1e-10) requests of 1e-12
  // (rank 25), 1e-8 (rank 19) and 1e-6 (rank 15) left M0, M2, M3 within 9.6e-12, 7.9e-12 and 1.0e-10 of a
  // tight reference. The rank sets the cost of a right-hand side (2 R FFTs): 19 instead of 25 is ~30% less.
  // Why 10 rtol: effective_lowrank_tolerance().
  double lowrank_tolerance = 0.0;
  // Relative entry error of the cheaper kernel form used for J·v (approximated kernels only; Newton's
  // method needs only an approximate Jacobian). 0 uses the right-hand side's form. At 1e-2 instead of 1e-4
  // the ballistic kernel (N = 5000, rtol 1e-6, t = 100) took the same steps and linear iterations (680 and
  // 1118 at λ = 0.01; 628/1038 against 632/1072 at λ = 0.1; 200/221 against 205/234 at λ = 1) at 15-20 %
  // less CPU time (bench/results/log/cvode-active-range.md).
  double jacobian_tolerance = 1e-2;
  std::size_t dense_limit = 4000;  // bdf_dense refuses larger N
  // Called after every internal step with the time reached (for progress reports); may be empty.
  std::function<void(double t)> progress;
  // Called after every internal step with the time reached and the step's densities n_1..n_N (the solution
  // the step accepted, before any output projection); may be empty. A record finer than the outputs where a
  // feature is narrower than their spacing: far below the Hopf curve a relaxation burst lasts ~1e-4 of a
  // period, and the steps resolve it while 400 outputs a period do not (limit_cycle.hpp, cycle_start_from_run).
  std::function<void(double t, std::span<const double> n)> on_step;
  double effective_lowrank_tolerance() const;
  double effective_atol() const { return atol > 0.0 ? atol : 1e-2 * rtol; }
  void validate() const;  // InputError for a field outside its option row's range (integrator_option_rows)
};

// The options of the integrator as a scene and Python give them: key, range, doc and the field each sets.
const OptionRows<IntegratorOptions>& integrator_option_rows();

struct IntegratorStatistics {
  long steps = 0, rhs_evaluations = 0, linear_iterations = 0, jacobian_vector_products = 0;
  long jacobian_evaluations = 0, preconditioner_setups = 0, preconditioner_solves = 0;
  long error_test_failures = 0, nonlinear_failures = 0, linear_convergence_failures = 0;
  double wall_seconds = 0.0;
  std::size_t kernel_rank = 0;            // rank of the separable kernel form (fast path)
  double kernel_relative_error = 0.0;     // its measured max relative entry error
  std::size_t negative_densities = 0;     // most entries < 0 at any output (tolerance level, not clipped)
  double most_negative_density = 0.0;
  double atol_floor = 0.0;                // the absolute lower bound of atol_k used (floor · largest n_k(0))
  // Negative densities beyond the tolerance, n_k < -atol_k, at any output: the integrator let an error
  // larger than it was asked to grow (round-off and tolerance-level values, |n_k| < atol_k, are not counted).
  std::size_t negative_beyond_tolerance = 0;  // most such entries at one output
  double most_negative_beyond_tolerance = 0.0;  // the most negative of them (0 if none), at size k and time t
  std::size_t most_negative_size = 0;
  double most_negative_time = 0.0;
  // The adaptive active size range (solvers/rates.hpp, Rates::ActiveRangeStatistics): its final and mean
  // size and the FFT work it left, relative to the full range.
  std::size_t active_size_final = 0;
  double active_size_mean = 0.0;
  double fft_work_fraction = 1.0;
  double stiff_from = -1.0;  // auto: the time from which BDF took over from the explicit method (-1: never)
};

// Called at each output time with the densities (sizes 1..N) and the mass leaked so far (drop).
using OutputCallback = std::function<void(double t, std::span<const double> n, double leaked_mass)>;

// A continuation from a state an earlier run reported at one of its output times: the densities (one per
// class) and the leaked mass at `time`. The tolerances are those of the model's start, as in the
// uninterrupted run, and the conserved mass Σ k n_k + L that of the restart's state; CVODE's BDF history (order, step size, Nordsieck array) is not kept — the
// continuation starts at order 1 — so it agrees with the uninterrupted run within the integration tolerance,
// not to the bit.
struct IntegratorRestart {
  double time = 0.0;
  std::vector<double> densities;
  double leaked_mass = 0.0;
};

// Integrates from t = 0 (or restart->time) to each of `output_times` (increasing, > 0; t = 0 itself is
// reported if listed; with a restart, only the times after it). Throws std::runtime_error with CVODE's flag
// and the time reached if the integrator fails.
IntegratorStatistics integrate(const AggregationModel& model, std::span<const double> output_times,
                               const IntegratorOptions& options, const OutputCallback& on_output,
                               const IntegratorRestart* restart = nullptr);

}  // namespace aggkit

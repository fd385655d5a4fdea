// locate_hopf (declared in solvers/stability.hpp): λ_crit(a) of the brownian kernel (i/j)^a + (j/i)^a,
// where the rightmost complex pair of the Jacobian at the steady state crosses Re μ = 0.
#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <exception>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>

#include "analysis/input_error.hpp"
#include "solvers/discretisation.hpp"
#include "solvers/stability.hpp"

namespace aggkit {

namespace {

struct Sample {
  double x = 0;          // ln λ
  double growth = 0;     // Re μ of the rightmost complex pair (rightmost eigenvalue if none is complex)
  double omega = 0;      // Im μ of that pair (0 if none)
  std::vector<double> n; // the steady state
};

class GrowthRate {
 public:
  GrowthRate(const AggregationModel& base, double a, const HopfOptions& options) : base_(base), a_(a), options_(options) {
    base_.kernel = Kernel::brownian(a);  // throws InputError for a outside [0, 1]
  }

  Sample at(double x, HopfPoint& point) {
    for (const Sample& s : samples_)  // the root finder asks again for the ends it was given
      if (s.x == x) return s;
    AggregationModel model = base_;
    model.lambda = ShatteringRate::constant(std::exp(x));
    // Continuation: start from the steady state at the nearest λ already solved.
    const Sample* nearest = nullptr;
    for (const Sample& s : samples_)
      if (!nearest || std::abs(s.x - x) < std::abs(nearest->x - x)) nearest = &s;
    SteadyStateResult steady;
    if (nearest) {
      // Along λ in steps of at most 0.5 in ln λ, Newton only: one long jump (a bracket stepped by ln 3)
      // can land on another root of the truncated system, whose complex pair may be stable although the
      // branch's is not (a = 0.59: "stable" at 5.7e-11 on such a root, unstable on the branch below 7.07e-11).
      // No other start either: from a root on the branch, a failed path means this λ has no positive root
      // near the branch (too short a truncation, or below where the grid's roots stay positive), and a CVODE
      // start would cost minutes at small λ only to land on another root.
      steady = follow_branch(model, nearest->n, a_, nearest->x, x);
    } else if (!options_.start.empty()) {
      // The caller's state at a nearby (a, λ), cut or extended to this N (carried onto this grid's classes
      // when either is graded).
      std::vector<double> guess = make_discretisation(model)->carry(options_.start_sizes, options_.start);
      steady = branch_start()
                   ? follow_branch(model, std::move(guess), options_.start_a, std::log(options_.start_lambda), x)
                   : solve_steady_state(model, options_.steady, guess);
    }
    // The solver's own start (CVODE) only where nothing on the branch is known (at a = 0.58, λ = 1e-14 the
    // CVODE starts took minutes per λ).
    if (!steady.converged && !nearest && !branch_start()) steady = solve_steady_state(model, options_.steady);
    ++point.evaluations;
    if (!steady.converged)
      throw std::runtime_error("locate_hopf: no steady state at a = " + format_value(point.a) +
                               ", lambda = " + format_value(std::exp(x)) + ": " + steady.note);
    // The eigenvalues nearest σ = 0 are asked for: at small λ the oscillating pair is slow (|μ| ≈ 3.8e-9 at
    // a = 0.59, λ = 5.7e-11) and real modes nearer 0 crowd it out of a short list — with 6 the search saw
    // only a stable pair there, on the branch whose pair has Re μ = +3.4e-11. On the graded grid the
    // shift-invert solves are one dense LU, so 16 cost little more.
    StabilityOptions stability = options_.stability;
    if (make_discretisation(model)->dense_solves())
      stability.krylov_eigenvalues = std::max(stability.krylov_eigenvalues, 16);
    const StabilityResult spectrum = analyse_stability(model, steady.n, 6, stability);
    Sample s;
    s.x = x;
    s.n = std::move(steady.n);
    const std::complex<double> pair = rightmost_complex_pair(spectrum.rightmost);
    if (std::isnan(pair.real())) {
      s.growth = spectrum.rightmost.front().real();
    } else {
      s.growth = pair.real();
      s.omega = pair.imag();
    }
    if (!spectrum.rightmost.empty() && spectrum.rightmost.front().imag() == 0.0 && spectrum.rightmost.front().real() > 0.0)
      point.note += "a real eigenvalue is positive at lambda = " + format_value(std::exp(x)) + "; ";
    samples_.push_back(s);
    return samples_.back();
  }

 private:
  // The steady state at (a_, e^x) on model's grid by natural-parameter continuation from `guess`, a state on
  // this grid at (a0, e^x0) (the start state of HopfOptions carried onto it, or a sample). Each step starts Newton from the
  // last step's root and nowhere else (no CVODE restarts), so a failed step means the branch was lost:
  // the result is then not converged.
  SteadyStateResult follow_branch(AggregationModel model, std::vector<double> guess, double a0, double x0,
                                  double x) const {
    const int steps = std::max({1, int(std::ceil(std::abs(a_ - a0) / 0.002)), int(std::ceil(std::abs(x - x0) / 0.5))});
    SteadyStateOptions steady = options_.steady;
    steady.start_retries = 0;
    SteadyStateResult result;
    for (int step = 1; step <= steps; ++step) {
      const double f = double(step) / steps;
      model.kernel = Kernel::brownian(a0 + f * (a_ - a0));
      model.lambda = ShatteringRate::constant(std::exp(x0 + f * (x - x0)));
      result = solve_steady_state(model, steady, guess);
      if (!result.converged) return result;
      guess = result.n;
    }
    return result;
  }

  // A steady state on the branch, at a known (a, λ), was given (HopfOptions::start, start_a, start_lambda).
  bool branch_start() const { return options_.start_lambda > 0.0 && !options_.start.empty(); }

  AggregationModel base_;
  double a_;
  HopfOptions options_;
  std::vector<Sample> samples_;
};

}  // namespace

HopfPoint locate_hopf(const AggregationModel& base, double a, double lambda_lo, double lambda_hi,
                      double relative_tolerance) {
  return locate_hopf(base, a, lambda_lo, lambda_hi, relative_tolerance, HopfOptions{});
}

HopfPoint locate_hopf(const AggregationModel& base, double a, double lambda_lo, double lambda_hi,
                      double relative_tolerance, const HopfOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  const std::clock_t cpu_started = std::clock();
  if (!(lambda_lo > 0.0) || !std::isfinite(lambda_lo))
    throw InputError("lambda_lo", format_value(lambda_lo), "a finite shattering rate > 0");
  if (!(lambda_hi > lambda_lo) || !std::isfinite(lambda_hi))
    throw InputError("lambda_hi", format_value(lambda_hi), "a finite shattering rate > lambda_lo");
  if (!(relative_tolerance > 0.0 && relative_tolerance < 1.0))
    throw InputError("relative_tolerance", format_value(relative_tolerance), "a number in (0, 1)");
  HopfPoint point;
  point.a = a;
  GrowthRate growth(base, a, options);
  // Stable end first: its steady state is the easiest start (CVODE relaxes to it).
  auto finish = [&] {
    point.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    point.cpu_seconds = double(std::clock() - cpu_started) / CLOCKS_PER_SEC;
    return point;
  };
  const double span = std::log(lambda_hi / lambda_lo);
  int steps = 0;
  // No positive steady state at lambda_hi (a guess far below λ_crit, where the truncated system's roots go
  // negative): step the bracket up to where one exists.
  // The steps double (span, 2 span, 4 span, ...): such a guess can be off by tens of e-folds, and a positive
  // root above the crossing is as good a start as one just above it (the search then walks down).
  Sample upper;
  for (double x = std::log(lambda_hi), step = span;; x += step, step *= 2) {
    try {
      upper = growth.at(x, point);
      break;
    } catch (const std::runtime_error& e) {
      if (steps >= options.bracket_steps) {
        point.lambda_no_steady = std::exp(x);
        point.note += std::string("no steady state at lambda_hi = ") + format_value(std::exp(x)) + ": " + e.what();
        return finish();
      }
      ++steps;
    }
  }
  if (steps > 0) point.note += "no steady state below lambda = " + format_value(std::exp(upper.x)) + "; ";
  // Crossing above the bracket: step it up (the old upper end becomes the lower one), keeping the stable
  // end's steady state as the next start.
  Sample lower;
  bool have_lower = false;
  while (upper.growth >= 0.0 && steps < options.bracket_steps) {
    ++steps;
    lower = upper;
    have_lower = true;
    upper = growth.at(lower.x + span, point);
  }
  if (upper.growth >= 0.0) {
    point.note += "unstable at lambda_hi = " + format_value(std::exp(upper.x)) + ": lambda_crit > that";
    return finish();
  }
  if (!have_lower) {
    try {
      lower = growth.at(std::log(lambda_lo), point);
      // Crossing below the bracket: step it down.
      while (lower.growth < 0.0 && steps < options.bracket_steps) {
        ++steps;
        upper = lower;
        lower = growth.at(upper.x - span, point);
      }
    } catch (const std::runtime_error& e) {
      // Small λ with a short truncation: the quasi-steady state may have no positive root (a larger N is
      // needed); the bracket cannot be closed, which is a result, not a failure of the search.
      point.lambda_no_steady = std::exp(upper.x - span);
      point.lambda_lowest_steady = std::exp(upper.x);
      point.note += std::string("no steady state at lambda_lo (raise lambda_lo or N); stable down to lambda = ") +
                    format_value(std::exp(upper.x)) + ": " + e.what();
      return finish();
    }
  }
  if (lower.growth < 0.0) {
    point.note += "stable at lambda_lo = " + format_value(std::exp(lower.x)) + ": lambda_crit < that (or no Hopf point)";
    return finish();
  }
  if (steps > 0) point.note += "bracket stepped " + std::to_string(steps) + " times; ";
  // Brent's method (gsl_root_fsolver_brent: inverse quadratic interpolation and secant steps, bisection
  // whenever they do not shrink the bracket fast enough) on g(ln λ): lower has g ≥ 0, upper g < 0. Every
  // iterate keeps a bracket [x_lower, x_upper] of evaluated points around the crossing; it is narrowed
  // until λ_upper / λ_lower ≤ 1 + relative_tolerance (gsl_root_test_interval with that width in ln λ).
  // GSL's Brent resolves the root to machine precision, so once the iterates converge from one side
  // (the other end of the bracket stays put) it would spend evaluations — each a steady state and a
  // spectrum — on ε-sized steps. As in Brent's own algorithm with a user tolerance, a step shorter than a
  // quarter of the wanted width is therefore followed by a probe half a width beyond the root estimate,
  // which closes the bracket (or moves its far end), and the solver restarts on the narrowed bracket
  // (its ends are cached: no new evaluations).
  // An evaluation that throws (no steady state) is parked and rethrown after the solver is freed; GSL's
  // abort-on-error handler is switched off meanwhile, and its status codes are checked instead.
  const double width = std::log1p(relative_tolerance);
  struct Call {
    GrowthRate* growth;
    HopfPoint* point;
    std::exception_ptr error;
  } call{&growth, &point, nullptr};
  gsl_function function;
  function.function = [](double x, void* data) {
    auto* c = static_cast<Call*>(data);
    if (c->error) return std::numeric_limits<double>::quiet_NaN();
    try {
      return c->growth->at(x, *c->point).growth;
    } catch (...) {
      c->error = std::current_exception();
      return std::numeric_limits<double>::quiet_NaN();  // GSL then stops with GSL_EBADFUNC
    }
  };
  function.params = &call;
  struct Solver {
    gsl_root_fsolver* s = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
    gsl_error_handler_t* previous = gsl_set_error_handler_off();
    ~Solver() {
      gsl_root_fsolver_free(s);
      gsl_set_error_handler(previous);
    }
  } solver;
  if (!solver.s) throw std::bad_alloc();
  double x_lower = lower.x, x_upper = upper.x, previous_root = NAN;
  int status = gsl_root_fsolver_set(solver.s, &function, x_lower, x_upper);
  for (int iteration = 0; status == GSL_SUCCESS && x_upper - x_lower > width && iteration < 60; ++iteration) {
    status = gsl_root_fsolver_iterate(solver.s);
    if (status != GSL_SUCCESS) break;
    x_lower = gsl_root_fsolver_x_lower(solver.s);
    x_upper = gsl_root_fsolver_x_upper(solver.s);
    const double root = gsl_root_fsolver_root(solver.s);
    if (gsl_root_test_interval(x_lower, x_upper, width, 0.0) == GSL_SUCCESS) break;
    if (std::abs(root - previous_root) < 0.25 * width) {
      // Converging from one side: probe across the root, half a width towards the bracket's far end.
      const bool at_lower = root - x_lower < x_upper - root;
      const double probe = at_lower ? root + 0.5 * width : root - 0.5 * width;
      const double g_root = growth.at(root, point).growth, g_probe = function.function(probe, &call);
      if (call.error) break;
      if ((g_probe >= 0.0) != (g_root >= 0.0))
        (at_lower ? x_upper : x_lower) = probe, (at_lower ? x_lower : x_upper) = root;
      else
        (at_lower ? x_lower : x_upper) = probe;
      status = gsl_root_fsolver_set(solver.s, &function, x_lower, x_upper);
    }
    previous_root = root;
  }
  if (call.error) std::rethrow_exception(call.error);
  if (status != GSL_SUCCESS)
    throw std::runtime_error(std::string("locate_hopf: Brent iteration failed: ") + gsl_strerror(status));
  // The bracket's ends are evaluated points: take their samples (growth rate and ω).
  for (double end : {x_lower, x_upper}) {
    const Sample s = growth.at(end, point);  // cached, no new evaluation
    (s.growth >= 0.0 ? lower : upper) = s;
  }
  // The crossing from the final bracket's true growth rates (linear in ln λ); the bound is the bracket.
  const double t = lower.growth / (lower.growth - upper.growth);
  point.found = true;
  point.lambda_crit = std::exp(lower.x + t * (upper.x - lower.x));
  point.lambda_tolerance = std::exp(upper.x) - std::exp(lower.x);
  point.omega = lower.omega + t * (upper.omega - lower.omega);
  point.steady_state = upper.n;
  point.steady_lambda = std::exp(upper.x);
  point.steady_sizes = make_discretisation(base)->output_sizes();
  if (upper.x - lower.x > width) point.note += "bracket not narrowed to the tolerance in 60 steps; ";
  return finish();
}

}  // namespace aggkit

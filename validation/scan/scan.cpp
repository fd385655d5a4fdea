#include "validation/scan/scan.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <sstream>

#include "analysis/input_error.hpp"
#include "validation/io/atomic_file.hpp"
#include "validation/io/progress.hpp"
#include "validation/scan/scan_criticality.hpp"
#include "validation/scan/scan_cycle_column.hpp"
#include "validation/scan/scan_lambda_crit.hpp"
#include "validation/runs/run_store.hpp"
#include "validation/runs/mpi_ranks.hpp"
#include "validation/scan/scan_output.hpp"
#include "validation/scan/scan_point.hpp"
#include "validation/io/text.hpp"

#include "solvers/hopf_curve.hpp"
#include "solvers/stability.hpp"

namespace aggkit {

namespace {

// One CVODE run of a scan: a grid point, a point repeated at 2N, or the refined repeat of a relaxing point
// (refined_plan at 2N). Results are cached in DIR/points under a name made of (a, λ, N) and "_refined", so
// a grid point and a truncation-check point at the same (a, λ, N) are one run.
struct Run {
  double a = 0, lambda = 0;
  std::size_t size = 0;
  bool refined = false;
  std::string key() const {
    std::string key = "a";  // appended piecewise: GCC 12 warns falsely (-Wrestrict) on "a" + std::string
    key += shortest_text(a);
    key += "_lambda";
    key += shortest_text(lambda);
    key += "_N";
    key += std::to_string(size);
    if (refined) key += "_refined";
    return key;
  }
  Run refinement() const { return {a, lambda, 2 * size, true}; }
  bool operator<(const Run& o) const {
    return std::tie(a, lambda, size, refined) < std::tie(o.a, o.lambda, o.size, o.refined);
  }
};

class RunCache {
 public:
  RunCache(const ScanPlan& plan, std::filesystem::path folder, std::ostream* progress)
      : plan_(plan), folder_(std::move(folder)), progress_(progress), world_(mpi_world()) {
    if (plan.refine) fine_ = refined_plan(plan);
  }

  std::optional<ScanRecord> finished(const Run& run) const {
    const std::optional<ScanRecord> r = parse_point_file(read_text_file(file(run)));
    if (!r || r->a != run.a || r->lambda != run.lambda || r->size != run.size) return std::nullopt;
    return r;
  }

  // Computes the runs not finished yet over the ranks, each rank drawing the next when it is free; every rank
  // returns when all have. With `refine` (and [scan] refine), a run that relaxes is followed at once by its
  // refined repeat. `first`, if given, is drawn before the runs.
  void compute(std::vector<Run> runs, const std::string& what, bool refine, const SerialTask* first = nullptr) {
    std::sort(runs.begin(), runs.end());
    runs.erase(std::unique(runs.begin(), runs.end(), [](const Run& x, const Run& y) { return !(x < y) && !(y < x); }),
               runs.end());
    refine = refine && fine_.has_value();
    const std::size_t offset = first ? 1 : 0;
    // Only the grid's points (size N; not the truncation check's 2N) are refined.
    const auto needs_refinement = [&](const Run& run) {
      if (!refine || run.refined || run.size != plan_.size()) return false;
      const std::optional<ScanRecord> r = finished(run);
      return r && is_relaxing(*r) && !finished(run.refinement());
    };
    const DistributedRuns done = compute_unfinished_runs(
        runs.size() + offset,
        [&](std::size_t i) {
          if (i < offset) return first->finished();
          const Run& run = runs[i - offset];
          return finished(run).has_value() && !needs_refinement(run);
        },
        [&](std::size_t i, std::size_t number, std::size_t count) {
          if (i < offset) return first->compute();
          const Run& run = runs[i - offset];
          if (!finished(run) && !compute_one(run, number, count)) return false;
          return !needs_refinement(run) || compute_one(run.refinement(), number, count);
        },
        "aggkit scan", what, progress_);
    reused_ += done.reused;
    failed_ += done.failed;
  }

  // The periods of the cycles continued down the columns: a grid point (size N, not refined) that its column
  // reached seeks no cycle of its own (ScanPoint::column_period).
  void take_column_cycles(const CycleColumns& columns) {
    for (const auto& [key, c] : columns)
      if (c.sustained()) column_periods_[key] = c.run.period;
  }

  std::size_t reused() const { return reused_; }
  std::size_t computed() const { return computed_; }
  std::size_t failed() const { return failed_; }

 private:
  std::filesystem::path file(const Run& run) const { return folder_ / (run.key() + ".csv"); }

  bool compute_one(const Run& run, std::size_t number, std::size_t count) {
    const ScanPlan& plan = run.refined ? *fine_ : plan_;
    const std::string label = "a = " + shortest_text(run.a) + ", lambda = " + shortest_text(run.lambda) +
                              ", N = " + std::to_string(run.size) +
                              (run.refined ? " refined (grid " + plan.scene.model.grid.describe() + ")" : "");
    Progress progress(progress_, std::chrono::seconds(10));
    progress.start(label, number, count, plan.scene.time.end);
    try {
      ScanPoint point{0, run.a, run.lambda};
      if (const auto c = column_periods_.find({run.a, run.lambda});
          !run.refined && run.size == plan_.size() && c != column_periods_.end())
        point.column_period = c->second;
      ScanRecord r = run_scan_point(plan, point, run.size, [&](double t, double end) {
                                      progress.set_end(end);
                                      progress.reached(t);
                                    },
                                    !run.refined);
      r.rank = world_.rank;
      write_file_atomically(file(run), point_file_text(r));
      ++computed_;
      if (progress_) {
        char line[512];
        std::snprintf(line, sizeof line, "aggkit scan: [rank %d] %zu/%zu %s: %s (%.1f s)\n", world_.rank, number, count,
                      label.c_str(), outcome_summary(r).c_str(), r.seconds);
        *progress_ << line << std::flush;
      }
      return true;
    } catch (const std::exception& e) {
      if (progress_) *progress_ << "aggkit scan: [rank " << world_.rank << "] " << label << " failed: " << e.what() << "\n";
      return false;
    }
  }

  const ScanPlan& plan_;
  std::optional<ScanPlan> fine_;  // refined_plan(plan_) with [scan] refine
  std::filesystem::path folder_;
  std::ostream* progress_;
  MpiWorld world_;
  std::map<std::pair<double, double>, double> column_periods_;  // (a, λ) -> the column's period there
  std::size_t reused_ = 0, computed_ = 0, failed_ = 0;
};

// One cached Hopf result (DIR/points/hopf_*.csv), or nullopt if the file is missing or damaged.
struct HopfRecord {
  bool found = false;
  double lambda_crit = 0, tolerance = 0, omega = 0;
  std::string note;
};
// The fields of the one row under `header` in a cached Hopf file, if the file is whole (one_row_record): at
// least `fields` fields, the second "yes" or "no" (found or converged).
std::optional<std::vector<std::string>> cached_hopf_row(const std::string& text, const std::string& header,
                                                        std::size_t fields) {
  auto f = one_row_record(text, header);
  if (!f || f->size() < fields || ((*f)[1] != "yes" && (*f)[1] != "no")) return std::nullopt;
  return f;
}

std::optional<HopfRecord> parse_hopf_file(const std::string& text, const std::string& header) {
  const auto row = cached_hopf_row(text, header, 5);
  if (!row) return std::nullopt;
  const std::vector<std::string>& f = *row;
  const auto lambda_crit = record_number(f[2]), tolerance = record_number(f[3]), omega = record_number(f[4]);
  if (!lambda_crit || !tolerance || !omega) return std::nullopt;
  return HopfRecord{f[1] == "yes", *lambda_crit, *tolerance, *omega, f.size() > 5 ? f[5] : ""};
}

// λ_crit(a) by locate_hopf over the scan's λ range at truncation `size`; cached in DIR/points like the runs
// (a damaged cache file is computed again, with a warning).
void hopf_lambda_crit(const ScanPlan& plan, const std::filesystem::path& points, std::vector<LambdaCritRow>& crit,
                      bool doubled, std::ostream* progress) {
  const MpiWorld world = mpi_world();
  const std::size_t size = doubled ? 2 * plan.size() : plan.size();
  const double lo = plan.lambda.front(), hi = plan.lambda.back();
  const auto file = [&](double a) {
    std::string name = "hopf_a";
    name += shortest_text(a);
    name += "_lambda" + shortest_text(lo) + "-" + shortest_text(hi) + "_N" + std::to_string(size) + ".csv";
    return points / name;
  };
  const std::string header = "a,found,lambda_crit,lambda_tolerance,omega,note";
  std::vector<double> todo;
  for (double a : plan.a) {
    if (parse_hopf_file(read_text_file(file(a)), header)) continue;
    if (progress && world.rank == 0 && std::filesystem::exists(file(a)))
      *progress << "aggkit scan: warning: " << file(a).string() << " is damaged; computing that point again\n";
    todo.push_back(a);
  }
  mpi_barrier();
  if (progress && world.rank == 0 && !todo.empty())
    *progress << "aggkit scan: locating the Hopf point lambda_crit(a) at N = " << size << " for " << todo.size()
              << " values of a\n" << std::flush;
  long failed = 0;
  for (std::size_t i = std::size_t(world.rank); i < todo.size(); i += std::size_t(world.size)) {
    try {
      const HopfPoint h = locate_hopf(point_model(plan, todo[i], lo, size), todo[i], lo, hi, 1e-3);
      std::string note = h.note;
      for (char& c : note)
        if (c == ',' || c == '\n') c = ';';
      write_file_atomically(file(todo[i]), header + "\n" + shortest_text(h.a) + "," + (h.found ? "yes" : "no") + "," +
                                               shortest_text(h.lambda_crit) + "," + shortest_text(h.lambda_tolerance) +
                                               "," + shortest_text(h.omega) + "," + note + "\n");
      if (progress)
        *progress << "aggkit scan: [rank " << world.rank << "] Hopf point a = " << shortest_text(todo[i]) << ", N = " << size
                  << ": " << (h.found ? "lambda_crit = " + shortest_text(h.lambda_crit) : h.note) << "\n" << std::flush;
    } catch (const std::exception& e) {
      ++failed;
      if (progress) *progress << "aggkit scan: Hopf point a = " << shortest_text(todo[i]) << " failed: " << e.what() << "\n";
    }
  }
  mpi_sum(failed);
  for (auto& row : crit) {
    const std::optional<HopfRecord> h = parse_hopf_file(read_text_file(file(row.a)), header);
    if (!h) continue;  // its computation failed (counted and reported above)
    const bool found = h->found;
    const double lambda_crit = h->lambda_crit, tolerance = h->tolerance, omega = h->omega;
    const std::string note = h->note;
    if (doubled) {
      if (found && row.method == "hopf") {
        row.lambda_crit_2N = lambda_crit;
        row.change_2N = std::abs(lambda_crit - row.lambda_crit) / row.lambda_crit;
      }
      continue;
    }
    if (!found) {
      row.note += std::string(row.note.empty() ? "" : "; ") + "Hopf: " + note;
      continue;
    }
    const std::string grid = std::isfinite(row.lambda_crit)
                                 ? "grid bracket [" + shortest_text(row.lambda_sustained) + " " +
                                       shortest_text(row.lambda_relaxing) + "]"
                                 : "grid: " + row.note;
    row.method = "hopf";
    row.lambda_crit = lambda_crit;
    row.error = tolerance;
    row.period = omega > 0 ? 2 * std::acos(-1.0) / omega : std::nan("");
    row.lambda_crit_2N = row.change_2N = std::nan("");
    row.note = grid;
  }
}

// λ_crit(a) as the converged curve on the graded hopf_grid (solvers/hopf_curve.hpp), one file per a in
// DIR/points. A continuation from the largest a down, so one rank runs it whole while the others compute the
// grid's points (converge_hopf_curve is the task drawn first; read_converged_lambda_crit reads the files).
const std::string hopf_curve_header =
    "a,converged,lambda_crit,bracket,omega,N,lambda_crit_half,change,resolved,ratio,lambda_crit_2K,change_2K,"
    "lambda_crit_half_ratio,change_half_ratio,note";

std::filesystem::path hopf_curve_file(const ScanPlan& plan, const std::filesystem::path& points, double a) {
  std::string name = "hopfcurve_a";
  name += shortest_text(a) + "_K" + std::to_string(plan.hopf_grid.resolved) + "_r" + shortest_text(plan.hopf_grid.ratio) +
          "_" + scheme_name(plan.hopf_grid.scheme) + ".csv";
  return points / name;
}

std::optional<std::vector<std::string>> read_hopf_curve_file(const ScanPlan& plan, const std::filesystem::path& points,
                                                              double a) {
  auto row = cached_hopf_row(read_text_file(hopf_curve_file(plan, points, a)), hopf_curve_header, 14);
  if (!row) return std::nullopt;
  std::vector<std::string>& f = *row;
  f.resize(15);
  for (std::size_t i = 2; i < 14; ++i)  // numbers (empty: NaN); a damaged file is computed again
    if (!record_number(f[i], /*empty_is_nan=*/true)) return std::nullopt;
  return f;
}

std::vector<double> hopf_curve_todo(const ScanPlan& plan, const std::filesystem::path& points) {
  std::vector<double> todo;
  for (auto it = plan.a.rbegin(); it != plan.a.rend(); ++it)
    if (!read_hopf_curve_file(plan, points, *it)) todo.push_back(*it);
  return todo;
}

// Computes the values of a not in DIR/points yet (on the calling rank alone); false if it failed. The first
// guess is λ_crit of the nearest larger a already computed (a resumed curve), else a rough locate_hopf: the
// same guess whichever rank runs it and whatever the grid's points show.
bool converge_hopf_curve(const ScanPlan& plan, const std::filesystem::path& points, std::ostream* progress) {
  const std::vector<double> todo = hopf_curve_todo(plan, points);
  if (todo.empty()) return true;
  const int rank = mpi_world().rank;
  try {
    AggregationModel base = point_model(plan, todo.front(), plan.lambda.front(), plan.size());
    base.grid = plan.hopf_grid;
    double guess = NAN;
    for (double a : plan.a)  // increasing: the first one above todo.front() with a value is the nearest
      if (const auto f = read_hopf_curve_file(plan, points, a); a > todo.front() && !std::isfinite(guess) && f) {
        const double value = std::stod((*f)[2]);
        if (value > 0) guess = value;
      }
    if (!std::isfinite(guess)) {
      // A rough first guess is enough (hopf_curve brackets from it): a coarser grid (a = 1: K = 16, r = 1.08
      // gives λ_crit 0.2 % off in 4 s, against 85 s on K = 64, r = 1.02) over the top three decades of the
      // scan's λ (its bracket stepped down by up to 30 widths if λ_crit lies lower). Below λ ~ 1e-9 a root
      // may not be positive, and the search would stop there.
      AggregationModel coarse = base;
      coarse.grid.resolved = std::max<std::size_t>(8, base.grid.resolved / 4);
      coarse.grid.ratio = std::min(1.5, 1 + 4 * (base.grid.ratio - 1));
      const double lo = std::max(plan.lambda.front(), plan.lambda.back() * 1e-3), hi = plan.lambda.back();
      HopfOptions rough;
      rough.bracket_steps = 30;
      const HopfPoint h = lo < hi ? locate_hopf(coarse, todo.front(), lo, hi, 1e-2, rough) : HopfPoint{};
      guess = h.found ? h.lambda_crit : std::sqrt(lo * hi);
    }
    if (progress)
      *progress << "aggkit scan: [rank " << rank << "] converging lambda_crit(a) on the grid " << plan.hopf_grid.describe()
                << " for " << todo.size() << " values of a (from a = " << shortest_text(todo.front()) << ", guess "
                << shortest_text(guess) << ")\n" << std::flush;
    HopfCurveOptions options;
    // On the graded grid the model's N (size) is the truncation the scan stands on (the scene chose it for
    // its smallest λ): no N beyond it.
    if (plan.size() >= 2 * options.min_size) {
      options.max_size = plan.size();
      // Classes grow only as log N, so each a starts at N = 1024 / guess rather than 8 / guess: the roots stay
      // positive down to λ ≈ 25 / N (a = 0.6, r = 1.02), and a guess 30 times above λ_crit still brackets it.
      options.size_per_inverse_lambda = 1024;
    }
    hopf_curve(base, todo, guess, std::size_t(std::ceil(8.0 / guess)), options, [&](const ConvergedHopfPoint& p) {
      std::string note = p.note;
      for (char& c : note)
        if (c == ',' || c == '\n') c = ';';
      const auto n = [](double x) { return shortest_text(x); };
      write_file_atomically(hopf_curve_file(plan, points, p.a),
                            hopf_curve_header + "\n" + n(p.a) + "," + (p.converged ? "yes" : "no") + "," +
                                n(p.lambda_crit) + "," + n(p.bracket) + "," + n(p.omega) + "," + std::to_string(p.size) +
                                "," + n(p.lambda_crit_half) + "," + n(p.change) + "," + std::to_string(p.resolved) + "," +
                                n(p.ratio) + "," + n(p.lambda_crit_2K) + "," + n(p.change_K) + "," +
                                n(p.lambda_crit_fine_ratio) + "," + n(p.change_ratio) + "," + note + "\n");
      if (progress)
        *progress << "aggkit scan: [rank " << rank << "] lambda_crit(" << shortest_text(p.a) << ") = "
                  << shortest_text(p.lambda_crit) << " at N = " << p.size << " (" << p.unknowns << " classes), changes N "
                  << shortest_text(p.change) << ", 2K " << shortest_text(p.change_K) << ", (r-1)/2 "
                  << shortest_text(p.change_ratio) << (p.converged ? "" : ": NOT CONVERGED " + p.note) << "\n"
                  << std::flush;
    });
    return true;
  } catch (const std::exception& e) {
    if (progress) *progress << "aggkit scan: [rank " << rank << "] the converged Hopf curve failed: " << e.what() << "\n";
    return false;
  }
}

// The converged curve's values into lambda_crit.csv's rows (every rank, after converge_hopf_curve).
void read_converged_lambda_crit(const ScanPlan& plan, const std::filesystem::path& points, std::vector<LambdaCritRow>& crit) {
  for (auto& row : crit) {
    const auto f = read_hopf_curve_file(plan, points, row.a);
    if (!f) continue;
    const auto number = [](const std::string& x) { return x.empty() ? NAN : std::stod(x); };
    const double lambda_crit = number((*f)[2]);
    if (!(lambda_crit > 0)) {
      row.note += std::string(row.note.empty() ? "" : "; ") + "converged Hopf curve: " + (*f)[14];
      continue;
    }
    const std::string grid = std::isfinite(row.lambda_crit) ? "grid bracket [" + shortest_text(row.lambda_sustained) + " " +
                                                                  shortest_text(row.lambda_relaxing) + "]"
                                                            : "grid: " + row.note;
    const double omega = number((*f)[4]);
    row.method = "hopf-converged";
    row.lambda_crit = lambda_crit;
    row.error = number((*f)[3]);
    row.period = omega > 0 ? 2 * std::acos(-1.0) / omega : NAN;
    row.size = std::stoul((*f)[5]);
    row.lambda_crit_2N = lambda_crit;
    row.change_2N = number((*f)[7]);
    row.resolved = std::stoul((*f)[8]);
    row.ratio = number((*f)[9]);
    row.lambda_crit_2K = number((*f)[10]);
    row.change_2K = number((*f)[11]);
    row.lambda_crit_half_ratio = number((*f)[12]);
    row.change_half_ratio = number((*f)[13]);
    row.converged = (*f)[1];
    row.note = grid + ((*f)[14].empty() ? "" : "; " + (*f)[14]);
  }
}

// A relaxing verdict stands only if its refined repeat relaxes too, towards a steady state that linear
// stability finds stable on the refined grid; and a spectrum's verdict only if the refined grid's spectrum
// agrees on stability (else the grid does not resolve the point: unresolved, with both said in the note).
void judge_by_refined(const ScanRecord& fine, const std::string& fine_grid, ScanRecord& r) {
  r.regime_refined = fine.regime;
  const bool unstable = fine.regime_stability == "sustained";
  if (!is_relaxing(fine) || unstable) {
    r.note = "was " + r.regime + " in the run; on the refined grid (N = " + std::to_string(fine.size) + ", " +
             fine_grid + ") it is " + fine.regime +
             (unstable ? " with an unstable steady state (Re mu = " + shortest_text(fine.rightmost_real) + ")" : "") +
             (fine.note.empty() ? "" : " (" + fine.note + ")") + (r.note.empty() ? "" : "; " + r.note);
    r.regime = "unresolved";
    r.agree = "";
  }
  const bool stable = r.regime_stability == "damped" || r.regime_stability == "steady";
  if (stable && unstable && (r.verdict == "damped" || r.verdict == "steady")) {
    r.note = "the spectrum's verdict " + r.verdict + " is not kept: the refined grid's steady state is unstable; " + r.note;
    r.verdict = "unresolved";
  }
}

}  // namespace

namespace {

// Phase 2: λ_crit at 2N. From the grid, the two points that bracket λ_crit(a) are repeated at 2N: if both
// keep their regimes, λ_crit(2N) lies in the same bracket and the change is below the bracket's width.
void check_brackets_at_2N(RunCache& cache, std::size_t N, std::vector<LambdaCritRow>& crit) {
  std::vector<Run> bracket_runs;
  for (const auto& row : crit)
    if (std::isfinite(row.lambda_crit)) {
      bracket_runs.push_back({row.a, row.lambda_sustained, 2 * N});
      bracket_runs.push_back({row.a, row.lambda_relaxing, 2 * N});
    }
  cache.compute(bracket_runs, "lambda_crit brackets at 2N = " + std::to_string(2 * N), false);
  for (auto& row : crit) {
    if (!std::isfinite(row.lambda_crit)) continue;
    const auto below = cache.finished({row.a, row.lambda_sustained, 2 * N});
    const auto above = cache.finished({row.a, row.lambda_relaxing, 2 * N});
    if (!below || !above) continue;
    const bool kept = below->regime == "sustained" && (above->regime == "damped" || above->regime == "steady");
    if (kept) {
      row.lambda_crit_2N = row.lambda_crit;
      row.change_2N = 0;
      row.note += std::string(row.note.empty() ? "" : "; ") + "at 2N the bracket keeps its regimes: |change| < the bracket width";
    } else {
      row.note += std::string(row.note.empty() ? "" : "; ") + "at 2N the bracket changes (" + below->regime + ", " +
                  above->regime + "): N too small";
    }
  }
}

// λ_crit(a) bracketed by the grid's time-series verdicts: one lambda_crit.csv row per a.
std::vector<LambdaCritRow> lambda_crit_rows_from_grid(const ScanPlan& plan,
                                                      const std::map<double, std::vector<ScanRecord>>& by_a) {
  std::vector<LambdaCritRow> crit;
  for (double a : plan.a) {
    const auto points = by_a.find(a);
    const GridLambdaCrit g = lambda_crit_from_grid(a, points == by_a.end() ? std::vector<ScanRecord>{} : points->second,
                                                   plan.lambda_log);
    LambdaCritRow row;
    row.a = a;
    row.lambda_crit = g.lambda_crit;
    row.error = g.error;
    row.method = "grid";
    row.lambda_sustained = g.lambda_sustained;
    row.lambda_relaxing = g.lambda_relaxing;
    row.size = plan.size();
    row.note = g.note;
    crit.push_back(row);
  }
  return crit;
}

// Rank 0: scan.csv, timing.csv, lambda_crit.csv, truncation_check.csv and the pictures, then the summary line.
void write_outputs(const ScanPlan& plan, const ScanOptions& options, const RunCache& cache,
                   const std::vector<ScanRecord>& records, const std::vector<LambdaCritRow>& crit,
                   const ScanOutcome& outcome) {
  const std::size_t N = plan.size();
  write_scan_csv(options.out / "scan.csv", records);
  write_timing_csv(options.out / "timing.csv", records);
  write_lambda_crit_csv(options.out / "lambda_crit.csv", crit);
  if (!plan.check_points.empty()) {
    std::vector<TruncationCheckRow> rows;
    for (const auto& [a, lambda] : plan.check_points) {
      const auto n = cache.finished({a, lambda, N});
      const auto n2 = cache.finished({a, lambda, 2 * N});
      if (n && n2) rows.push_back({*n, *n2});
    }
    write_truncation_check_csv(options.out / "truncation_check.csv", rows);
  }
  if (options.plot) {
    const std::string why = plot_phase_diagram(options.out / "scan.csv", options.out / "lambda_crit.csv",
                                               options.out / "phase_diagram.png", options.out / "bifurcation.png",
                                               plan.scene.name, plan.lambda_log);
    if (!why.empty() && options.progress) *options.progress << "aggkit scan: phase diagram not drawn: " << why << "\n";
  }
  if (options.progress) {
    *options.progress << "aggkit scan: " << records.size() << "/" << plan.point_count() << " points in "
                      << (options.out / "scan.csv").string();
    if (outcome.failed) *options.progress << "; " << outcome.failed << " runs failed (run again to retry them)";
    *options.progress << "\n";
  }
}

// Phase 0, with cycle columns: the Hopf bifurcation's criticality per a and the attracting cycles continued
// down each a's column, before the points, so that a point the column reached takes its cycle instead of
// searching and shooting its own (both cached in DIR/points; the later calls read them back). No columns:
// nothing is computed.
CycleColumns columns_first(const ScanPlan& plan, const std::filesystem::path& points, const SerialTask* beside,
                           std::ostream* progress) {
  if (plan.column_periods == 0) return {};  // > 0 implies stability and cycles (scan_plan.cpp)
  std::vector<LambdaCritRow> early(plan.a.size());
  for (std::size_t i = 0; i < plan.a.size(); ++i) early[i].a = plan.a[i];
  add_hopf_criticality(plan, points, early, progress);
  return follow_cycle_columns(plan, points, early, progress, beside);
}

}  // namespace

ScanOutcome run_scan(const ScanPlan& plan, const ScanOptions& options) {
  const MpiWorld world = mpi_world();
  const std::filesystem::path points = options.out / "points";
  prepare_points_folder(options.out, points);
  if (world.rank == 0)
    check_points_fingerprint(points, plan.fingerprint, ".csv", "aggkit scan",
                             "the scene's model, time grid or classification changed", options.progress);
  mpi_barrier();

  RunCache cache(plan, points, options.progress);
  const std::size_t N = plan.size();

  // The converged Hopf curve on a graded hopf_grid: drawn first with the columns, or else with the points,
  // so that one rank computes it beside them.
  const bool curve = plan.stability && !plan.hopf_grid.uniform();
  const SerialTask hopf{[&] { return hopf_curve_todo(plan, points).empty(); },
                        [&] { return converge_hopf_curve(plan, points, options.progress); }};
  const CycleColumns columns = columns_first(plan, points, curve ? &hopf : nullptr, options.progress);
  cache.take_column_cycles(columns);

  // Phase 1: the grid (each relaxing point followed by its refined repeat), the truncation-check points at N
  // and 2N (and the Hopf curve, where there are no columns).
  const bool curve_beside_points = curve && plan.column_periods == 0;
  std::vector<Run> runs;
  for (std::size_t i = 0; i < plan.point_count(); ++i) runs.push_back({plan.point(i).a, plan.point(i).lambda, N});
  for (const auto& [a, lambda] : plan.check_points) {
    runs.push_back({a, lambda, N});
    runs.push_back({a, lambda, 2 * N});
  }
  cache.compute(runs,
                "grid of " + std::to_string(plan.a.size()) + " a x " + std::to_string(plan.lambda.size()) +
                    " lambda at N = " + std::to_string(N) + (curve_beside_points ? ", and the converged Hopf curve" : ""),
                true, curve_beside_points ? &hopf : nullptr);

  // A relaxing verdict stands only if its refined repeat relaxes too, towards a steady state that linear
  // stability finds stable on the refined grid (every rank reads the same files).
  std::vector<ScanRecord> records;
  std::map<double, std::vector<ScanRecord>> by_a;
  const std::string fine_grid = plan.refine ? refined_plan(plan).scene.model.grid.describe() : "";
  for (std::size_t i = 0; i < plan.point_count(); ++i) {
    const ScanPoint p = plan.point(i);
    auto r = cache.finished({p.a, p.lambda, N});
    if (!r) continue;
    r->index = i;
    if (plan.refine && is_relaxing(*r)) {
      const std::optional<ScanRecord> fine = cache.finished(Run{p.a, p.lambda, N}.refinement());
      if (!fine) continue;  // its repeat failed (counted and reported): the point is not finished
      judge_by_refined(*fine, fine_grid, *r);
    }
    records.push_back(*r);
    by_a[p.a].push_back(*r);
  }
  std::vector<LambdaCritRow> crit = lambda_crit_rows_from_grid(plan, by_a);

  if (plan.check_lambda_crit) check_brackets_at_2N(cache, N, crit);

  // λ_crit(a) from the Hopf point of the linear stability (solvers/stability.hpp), where the grid gave only
  // a bracket.
  if (curve) {
    read_converged_lambda_crit(plan, points, crit);
  } else if (plan.stability) {
    hopf_lambda_crit(plan, points, crit, false, options.progress);
    if (plan.check_lambda_crit) hopf_lambda_crit(plan, points, crit, true, options.progress);
  }

  ScanOutcome outcome;
  outcome.points = plan.point_count();
  outcome.reused = cache.reused();
  outcome.computed = cache.computed();
  outcome.failed = cache.failed();
  outcome.exit_code = outcome.failed > 0 || records.size() < plan.point_count() ? 1 : 0;

  if (plan.stability) add_hopf_criticality(plan, points, crit, options.progress);
  if (plan.column_periods > 0) adopt_column_cycles(columns, plan.column_periods, records);
  if (world.rank == 0) write_outputs(plan, options, cache, records, crit, outcome);
  mpi_barrier();
  return outcome;
}

}  // namespace aggkit

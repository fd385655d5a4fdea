#include "validation/scan/scan_criticality.hpp"

#include <cmath>
#include <exception>
#include <optional>
#include <string>

#include "solvers/cycle_branch.hpp"
#include "solvers/steady_branch.hpp"
#include "validation/io/atomic_file.hpp"
#include "analysis/text.hpp"
#include "validation/runs/mpi_ranks.hpp"
#include "validation/runs/run_store.hpp"

namespace aggkit {
namespace {

// The normal form is taken at (1 − δ) λ_crit: near enough that the cubic truncation holds (the predicted M0
// half-range is within 1.5 % of the shot cycle at a = 0.95 and 0.7, bench/results/RESULTS.md), far enough that
// Re μ is not lost in the eigensolver's error.
constexpr double normal_form_distance = 0.05;
constexpr double branch_anchor = 0.1;  // as the scan points' steady branches (scan_point.cpp)

const char* const header = "a,found,lambda_crit_scan_grid,lyapunov,criticality,m0_half_range,grid,note";

struct Criticality {
  bool found = false;
  double lambda_crit = std::nan(""), lyapunov = std::nan(""), m0_half_range = std::nan("");
  std::string criticality, grid, note;
};

std::string csv_safe(std::string text) {
  for (char& c : text)
    if (c == ',' || c == '\n') c = ';';
  return text;
}

std::string file_text(double a, const Criticality& c) {
  return std::string(header) + "\n" + shortest_text(a) + "," + (c.found ? "yes" : "no") + "," +
         shortest_text(c.lambda_crit) + "," + shortest_text(c.lyapunov) + "," + c.criticality + "," +
         shortest_text(c.m0_half_range) + "," + csv_safe(c.grid) + "," + csv_safe(c.note) + "\n";
}

// The cached result, if the file is whole and was computed on `grid`.
std::optional<Criticality> parse_file(const std::string& text, const std::string& grid) {
  const auto fields = one_row_record(text, header);
  if (!fields || fields->size() < 7) return std::nullopt;
  const std::vector<std::string>& f = *fields;
  const auto lambda_crit = record_number(f[2]), lyapunov = record_number(f[3]), half_range = record_number(f[5]);
  if ((f[1] != "yes" && f[1] != "no") || f[6] != csv_safe(grid) || !lambda_crit || !lyapunov || !half_range)
    return std::nullopt;
  Criticality c;
  c.found = f[1] == "yes";
  c.lambda_crit = *lambda_crit;
  c.lyapunov = *lyapunov;
  c.criticality = f[4];
  c.m0_half_range = *half_range;
  c.grid = grid;
  c.note = f.size() > 7 ? f[7] : "";
  return c;
}

Criticality compute(const ScanPlan& plan, double a) {
  Criticality c;
  const AggregationModel model = point_model(plan, a, branch_anchor, plan.size());
  c.grid = model.grid.describe();
  SteadyBranch steady(model, branch_anchor);
  const HopfPoint h = hopf_on_branch(steady, model, a, plan.lambda.front());
  if (!h.found) {
    c.note = "no Hopf crossing on the scan's grid: " + h.note;
    return c;
  }
  c.lambda_crit = h.lambda_crit;
  CycleBranchOptions options;
  options.start_distance = normal_form_distance;
  CycleBranch branch(model, steady, h.lambda_crit, options);
  const HopfNormalForm& form = branch.normal_form();
  if (form.q.empty()) {
    c.note = "no normal form at lambda = " + shortest_text(branch.start_lambda());
    return c;
  }
  c.found = true;
  c.lyapunov = form.lyapunov;
  c.criticality = form.supercritical() ? "supercritical" : "subcritical";
  c.m0_half_range = form.m0_half_range();
  return c;
}

void report(std::ostream* progress, int rank, double a, const Criticality& c) {
  if (!progress) return;
  *progress << "aggkit scan: [rank " << rank << "] criticality a = " << shortest_text(a) << ": "
            << (c.found ? c.criticality + " (l1 = " + shortest_text(c.lyapunov) + " at lambda_crit = " +
                              shortest_text(c.lambda_crit) + " on the scan's grid)"
                        : c.note)
            << "\n" << std::flush;
}

}  // namespace

void add_hopf_criticality(const ScanPlan& plan, const std::filesystem::path& points, std::vector<LambdaCritRow>& crit,
                          std::ostream* progress, std::size_t dense_limit) {
  const MpiWorld world = mpi_world();
  const AggregationModel probe = point_model(plan, plan.a.front(), branch_anchor, plan.size());
  const std::string grid = probe.grid.describe();
  if (probe.unknowns() > dense_limit) {
    for (auto& row : crit)
      row.note += std::string(row.note.empty() ? "" : "; ") + "criticality not computed: " +
                  std::to_string(probe.unknowns()) + " classes (the normal form's dense solves stop at " +
                  std::to_string(dense_limit) + ")";
    return;
  }
  const auto file = [&](double a) {
    return points / ("hopf_criticality_a" + shortest_text(a) + "_N" + std::to_string(plan.size()) + ".csv");
  };
  std::vector<double> todo;
  for (double a : plan.a)
    if (!parse_file(read_text_file(file(a)), grid)) todo.push_back(a);
  mpi_barrier();
  if (progress && world.rank == 0 && !todo.empty())
    *progress << "aggkit scan: the Hopf bifurcation's criticality on the grid " << grid << " for " << todo.size()
              << " values of a\n" << std::flush;
  for (std::size_t i = std::size_t(world.rank); i < todo.size(); i += std::size_t(world.size)) {
    Criticality c;
    try {
      c = compute(plan, todo[i]);
    } catch (const std::exception& e) {
      c.grid = grid;
      c.note = std::string("criticality failed: ") + e.what();
    }
    write_file_atomically(file(todo[i]), file_text(todo[i], c));
    report(progress, world.rank, todo[i], c);
  }
  mpi_barrier();
  for (auto& row : crit) {
    const std::optional<Criticality> c = parse_file(read_text_file(file(row.a)), grid);
    if (!c) continue;
    row.lambda_crit_model_grid = c->lambda_crit;
    row.lyapunov = c->lyapunov;
    row.criticality = c->criticality;
    row.m0_half_range = c->m0_half_range;
    if (!c->found) row.note += std::string(row.note.empty() ? "" : "; ") + c->note;
  }
}

}  // namespace aggkit

#pragma once
// The Hopf bifurcation's criticality per a, on the scan's own model grid: λ_crit there (the steady branch's
// ladder and Brent, solvers/cycle_branch.hpp) and the normal form 5 % below it (solvers/hopf_normal_form.hpp):
// the first Lyapunov coefficient l1 (l1 < 0: supercritical, a stable cycle is born where the steady state loses
// stability; l1 > 0: subcritical, a bistable band above λ_crit) and the M0 half-range of the cycle it predicts
// [Kuznetsov2004, Sec. 3.5]. Distributed over the MPI ranks and cached in DIR/points/hopf_criticality_*.csv like the
// Hopf points: a resumed scan reads them.
#include <cstddef>
#include <filesystem>
#include <ostream>
#include <vector>

#include "validation/scan/scan_output.hpp"
#include "validation/scan/scan_plan.hpp"

namespace aggkit {

// Fills lambda_crit_model_grid, lyapunov, criticality and m0_half_range of each row (called on every rank).
// Grids of more than `dense_limit` classes are left out (the normal form factors the dense Jacobian), with a
// note on the row.
void add_hopf_criticality(const ScanPlan& plan, const std::filesystem::path& points, std::vector<LambdaCritRow>& crit,
                          std::ostream* progress, std::size_t dense_limit = 1200);

}  // namespace aggkit

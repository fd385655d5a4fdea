#pragma once
// λ_crit(a) from a scan grid: sustained oscillations for λ < λ_crit [Brilliantov2018; Kalinov2022, Sec. 5.2], so the boundary lies
// between the largest sustained λ and the next larger λ that relaxes (steady or damped). The estimate is the
// midpoint of that bracket (geometric for log-spaced λ) and its error the distance to the bracket's ends:
// the true crossing lies in the bracket as long as the two points are classified right. Only converged
// sustained verdicts count (irregular and tentative points are left out and counted in the note).
#include <limits>
#include <string>
#include <vector>

#include "validation/scan/scan_record.hpp"

namespace aggkit {

struct GridLambdaCrit {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  double a = 0;
  double lambda_crit = nan;  // NaN when the grid holds no bracket (see note)
  double error = nan;        // |λ_crit - true crossing| bound
  double lambda_sustained = nan, lambda_relaxing = nan;  // the bracket
  std::string note;          // "below the grid", "above the grid", "not monotone in λ"
};

// `records`: the points of one a (any order, any N: only those of `size` are used).
GridLambdaCrit lambda_crit_from_grid(double a, std::vector<ScanRecord> records, bool log_spacing);

}  // namespace aggkit

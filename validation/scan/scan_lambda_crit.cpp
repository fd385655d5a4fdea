#include "validation/scan/scan_lambda_crit.hpp"

#include <algorithm>
#include <cmath>

#include "validation/io/text.hpp"

namespace aggkit {

GridLambdaCrit lambda_crit_from_grid(double a, std::vector<ScanRecord> records, bool log_spacing) {
  GridLambdaCrit result;
  result.a = a;
  // Points without a verdict (irregular) say nothing about the boundary.
  // Neither do tentative sustained verdicts (fewer cycles in the tail than the convergence check needs, or
  // an amplitude still growing or drifting): long-period transients at small λ look like that.
  const std::size_t before = records.size();
  std::erase_if(records, [](const ScanRecord& r) {
    return (r.regime != "sustained" && r.regime != "damped" && r.regime != "steady") ||
           (r.regime == "sustained" && !r.converged);
  });
  const std::size_t unused = before - records.size();
  std::sort(records.begin(), records.end(), [](const ScanRecord& x, const ScanRecord& y) { return x.lambda < y.lambda; });
  if (records.empty()) {
    result.note = "no classified point";
    return result;
  }
  const auto sustained = [](const ScanRecord& r) { return r.regime == "sustained"; };
  // The largest sustained λ, and the first relaxing λ above it.
  const auto last_sustained = std::find_if(records.rbegin(), records.rend(), sustained);
  if (last_sustained == records.rend()) {
    result.note = "no sustained point: lambda_crit < " + shortest_text(records.front().lambda);
    return result;
  }
  const auto below = last_sustained.base() - 1;
  if (below + 1 == records.end()) {
    result.note = "all points up to the largest lambda sustained: lambda_crit > " + shortest_text(below->lambda);
    return result;
  }
  const double lo = below->lambda, hi = (below + 1)->lambda;
  result.lambda_sustained = lo;
  result.lambda_relaxing = hi;
  result.lambda_crit = log_spacing ? std::sqrt(lo * hi) : 0.5 * (lo + hi);
  result.error = hi - result.lambda_crit;  // >= λ_crit - lo for both midpoints
  if (std::any_of(records.begin(), below, [&](const ScanRecord& r) { return !sustained(r); }))
    result.note = "not monotone in lambda: relaxing points below the largest sustained one";
  if (unused > 0)
    result.note += std::string(result.note.empty() ? "" : "; ") + std::to_string(unused) +
                   " points without a converged verdict left out";
  return result;
}

}  // namespace aggkit

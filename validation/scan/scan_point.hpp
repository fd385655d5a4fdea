#pragma once
// One point of a scan: the CVODE run of the point's model over the scene's time grid, the time-series
// classification of the scan's moment over the tail, and (where available and asked for) the steady state
// and its linear stability.
#include <cstddef>
#include <functional>
#include <memory>

#include "validation/scan/scan_plan.hpp"
#include "validation/scan/scan_record.hpp"

namespace aggkit {

// Whether the steady-state/stability classification is part of this build (regime_stability columns).
bool scan_stability_available();

// A fresh store of steady-state branches for a plan (ScanPlan::branches).
std::shared_ptr<SteadyBranches> make_steady_branches();

// `size` is the truncation N of this run (the scene's, or 2N for the truncation check); `progress` receives
// the time reached and the run's end (may be empty). A damped or steady verdict that the run or the steady state does not
// support becomes "unresolved" (with `judge_relaxation`; a refined repeat keeps the time series' own
// verdict, which is what it is compared by). Throws what the integrator throws if the run fails.
ScanRecord run_scan_point(const ScanPlan& plan, const ScanPoint& point, std::size_t size,
                          const std::function<void(double t, double end)>& progress = {},
                          bool judge_relaxation = true);

}  // namespace aggkit

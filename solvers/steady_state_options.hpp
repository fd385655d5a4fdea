#pragma once
// The options of the SNES steady-state solver as a scene and Python give them (analysis/option_rows.hpp):
// key, range, doc and the field of SteadyStateOptions each sets; SteadyStateOptions::validate() checks
// exactly these ranges.
#include "analysis/option_rows.hpp"
#include "solvers/steady_state.hpp"

namespace aggkit {

const OptionRows<SteadyStateOptions>& steady_state_option_rows();
// The fields no scene gives (start_rtol, linear_tolerance, krylov_restart, max_krylov_iterations,
// start_retries), with their ranges. SteadyStateOptions::validate() checks both sets of rows.
const OptionRows<SteadyStateOptions>& steady_state_tuning_rows();

}  // namespace aggkit

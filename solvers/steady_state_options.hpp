#pragma once
// The options of the SNES steady-state solver as a scene and Python give them (analysis/option_rows.hpp):
// key, range, doc and the field of SteadyStateOptions each sets.
#include "analysis/option_rows.hpp"
#include "solvers/steady_state.hpp"

namespace aggkit {

const OptionRows<SteadyStateOptions>& steady_state_option_rows();

}  // namespace aggkit

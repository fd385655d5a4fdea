#include "particle/dem/dashpot_scheme.hpp"

#include <cstdio>
#include <limits>
#include <stdexcept>

namespace aggkit {

namespace {

std::string shortest(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

}  // namespace

DashpotScheme dashpot_scheme_from_word(std::string_view word) {
  if (word == "auto") return DashpotScheme::automatic;
  if (word == "explicit") return DashpotScheme::explicit_verlet;
  if (word == "implicit") return DashpotScheme::implicit;
  throw std::invalid_argument("dashpot scheme: one of auto, explicit, implicit");
}

const char* dashpot_scheme_word(DashpotScheme scheme) {
  switch (scheme) {
    case DashpotScheme::automatic: return "auto";
    case DashpotScheme::explicit_verlet: return "explicit";
    case DashpotScheme::implicit: return "implicit";
  }
  return "auto";
}

double implicit_dashpot_threshold(DashpotScheme scheme) {
  switch (scheme) {
    case DashpotScheme::automatic: return automatic_implicit_above;
    case DashpotScheme::explicit_verlet: return std::numeric_limits<double>::infinity();
    case DashpotScheme::implicit: return 0;
  }
  return automatic_implicit_above;
}

DashpotStepCheck check_dashpot_step(DashpotScheme scheme, double damping_factor, double dt, double contact_time, bool friction) {
  DashpotStepCheck check;
  check.damping_factor = damping_factor;
  check.steps_per_contact = contact_time / dt;
  check.implicit = damping_factor > 0 &&
                   (scheme == DashpotScheme::implicit || (scheme == DashpotScheme::automatic && !friction && damping_factor > automatic_implicit_above));
  if (dt > contact_time / 20)
    check.warnings.push_back("dt = " + shortest(dt) + " > t_c/20 = " + shortest(contact_time / 20) + " [Trivino2025, eq. 8] (t_c/dt = " +
                             shortest(check.steps_per_contact) + ")");
  if (!check.implicit && damping_factor > 1)
    check.warnings.push_back("the explicit dashpot runs above its stability limit: x = γ_n dt/m* = " + shortest(damping_factor) +
                             " > 1 (an overdamped approach is reversed and the pair gains energy)");
  return check;
}

}  // namespace aggkit

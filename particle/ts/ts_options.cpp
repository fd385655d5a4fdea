// The options of the time-stepping engine [Degond2024], bound to TsSettings and its DAHA parameters.
#include "analysis/text.hpp"
#include "particle/ts/time_stepping_aggregation.hpp"

namespace aggkit {

const OptionRows<TsSettings>& ts_option_rows() {
  using S = TsSettings;
  using B = Bind<S>;
  static const OptionRows<S> rows{{
      B::number("dt_factor", &S::dt_factor, left_open(0.0, 1.0),
                "Δt(0) = dt_factor · L / max|V(0)|, growing to 2Δt(0) at one cluster [Degond2024, Table 1]"),
      B::number("c_bar", [](auto& s) -> auto& { return s.daha.c_bar; }, left_open(0.0, 1e6),
                "damping c̄ of the DAHA (c = δ c̄ per iteration, at most 1/δ)"),
      B::number("delta", [](auto& s) -> auto& { return s.daha.delta; }, left_open(0.0, 10.0), "DAHA step δ"),
      B::number("alpha", [](auto& s) -> auto& { return s.daha.alpha; }, left_open(0.0, 1e6),
                "DAHA force coefficient α (attraction and multipliers)"),
      B::number("gamma", [](auto& s) -> auto& { return s.daha.gamma; }, closed(0.0, 1e6), "DAHA coefficient γ of the φλ∇φ term"),
      B::number("beta_bar", [](auto& s) -> auto& { return s.daha.beta_bar; }, left_open(0.0, 1e6), "multiplier rate β̄ (β = δ β̄)"),
      B::number("eps_c", [](auto& s) -> auto& { return s.daha.eps_c; }, left_open(0.0, 1.0),
                "ε_c: mean √|φ| over the links at convergence (paper units, R = 0.2)"),
      B::number("eps_s", [](auto& s) -> auto& { return s.daha.eps_s; }, left_open(0.0, 1.0),
                "ε_s: largest move of a sphere in the last iteration (paper units, R = 0.2)"),
      B::number("interaction_range", &S::interaction_range, closed(2.0, 1e6),  // links touch at 2R
                "Δ_W / R: links attract only within Δ_W; free spheres lie within Δ_W of a new link"),
      B::flag("contact_time", &S::contact_time,
              "merge a binary collision at its contact time (rewound along the flight, merged, flown on); "
              "false: every contact resolved from its end-of-flight overlap by the DAHA, as [Degond2024]"),
      B::number("substep_displacement", &S::substep_displacement, left_open(0.0, 1e6),
                "largest flight of a cluster in one substep, in diameters 2R: a longer step is "
                "flown in substeps, each followed by contact detection along the flown paths"),
      B::integer("max_iterations", [](auto& s) -> auto& { return s.daha.max_iterations; }, closed(1, 1e9),
                 "iteration cap of one minimisation (hits are counted)"),
      B::word("variant", &S::global, std::vector<std::pair<std::string, bool>>{{"local", false}, {"global", true}},
              "local: almost rigid clusters [Degond2024, Sec. 3.3]; global: every sphere of the clusters touched "
              "moves, all their pairs constrained (Sec. 3.1, O(n²))"),
      B::integer("cluster_threads", &S::threads, closed(1, 4096),
                 "workers for the minimisations of separate clusters in one step (results do not depend on it)"),
  }};
  return rows;
}

void TsSettings::validate() const {
  ts_option_rows().check(*this);
  if (daha.delta * daha.c_bar > 1.0)
    throw InputError("c_bar", option_text(nlohmann::json(daha.c_bar)),
                     "c_bar <= 1/delta = " + shortest_text(1.0 / daha.delta) + " (the damping δ c̄ of one iteration is at most 1)");
}

}  // namespace aggkit

#pragma once
// Observables: one registry (observable_registry.cpp) of everything a scene can ask for in
// `observe.series` (a value at every output time) and `observe.final` (the final configuration of a
// particle engine, written to <engine>/final.json, or for a profile to <engine>/<name>.csv). Each entry
// says what it reads of a state (its needs), so an engine that cannot give that is refused when the scene
// is checked, and a particle engine computes only what the scene asks. Adding an observable is one entry
// in observable_registry.cpp; `aggkit run --help` lists them from there.
#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "analysis/fractal_dimension.hpp"
#include "validation/observables/observed_state.hpp"
#include "validation/observables/particle_view.hpp"

namespace aggkit {

// What an observable reads of a state; what an engine's states can give (a bit set).
namespace need {
constexpr unsigned sizes = 1u << 0;        // the size distribution n_k
constexpr unsigned leaked_mass = 1u << 1;  // the mass that left through the truncation
constexpr unsigned positions = 1u << 2;    // particle positions, radii and the box
constexpr unsigned velocities = 1u << 3;
constexpr unsigned masses = 1u << 4;
constexpr unsigned clusters = 1u << 5;     // which cluster each particle belongs to
constexpr unsigned collisions = 1u << 6;   // pair collisions counted since t = 0 (CollisionStatistics)
constexpr unsigned virial = 1u << 7;       // the pair virial since t = 0 in a periodic box (CollisionStatistics)
constexpr unsigned kinetic = sizes | leaked_mass;                              // every kinetic engine
constexpr unsigned particles = sizes | positions | velocities | masses | clusters;  // every particle engine
}  // namespace need
std::string describe_needs(unsigned needs);  // "particle velocities, particle masses"

// A function-valued observable of one configuration: y against x.
struct Profile {
  std::string x_name, y_name;
  std::vector<double> x, y;
};

struct ObservableType {
  std::string form;         // as written in scenes: "M<p>", "n<k>", "clusters"
  std::string description;  // one line, for --help
  unsigned needs = 0;
  // The parameter of `name` if it has this form (p of M<p>, k of n<k>, 0 for a plain name), else nullopt.
  std::function<std::optional<double>(std::string_view name)> match;
  bool size_parameter = false;  // the parameter is a cluster size k (at most the largest size of the scene)
  // Exactly one of these is set: a number; a fitted exponent (final.json gets <name>, <name>_error,
  // <name>_fit_min, <name>_fit_max; a series gets the exponent); a profile (final only); a measure of a
  // whole series (final only, any engine: the form is "<measure>:<series>", e.g. oscillation_period:M0,
  // taken on each realization's series over observe.window, x(t) at uniformly spaced t).
  std::function<double(const ObservedState&, double parameter)> scalar;
  std::function<FractalFit(const ParticleView&)> fit;
  std::function<Profile(const ParticleView&)> profile;
  std::function<double(std::span<const double> t, std::span<const double> x)> of_series = {};
};

// Every observable kind, in the order --help lists them.
const std::vector<ObservableType>& observable_types();

class Observable {
 public:
  // The observable named `name`, or std::nullopt if it matches no form of the registry.
  static std::optional<Observable> from_name(std::string_view name);
  static std::string forms();  // the allowed forms, for messages

  const std::string& name() const { return name_; }  // as written in the scene
  const ObservableType& type() const { return *type_; }
  double parameter() const { return parameter_; }
  unsigned needs() const { return type_->needs; }
  bool is_profile() const { return bool(type_->profile); }
  bool is_series_measure() const { return bool(type_->of_series); }
  // The series a series measure is taken of: "M0" of "oscillation_period:M0"; empty for other observables.
  std::string source() const;
  // A series measure of x(t) (t uniformly spaced); NaN where it is undefined (no oscillation).
  double measure(std::span<const double> t, std::span<const double> x) const { return type_->of_series(t, x); }

  // The number for a series (a fit's exponent); NaN if the state lacks what it needs.
  double value(const ObservedState& state) const;
  // (key, value) pairs for final.json: the value, and for a fit its error and range.
  std::vector<std::pair<std::string, double>> final_values(const ObservedState& state) const;
  Profile profile(const ParticleView& view) const;

 private:
  Observable(std::string name, const ObservableType* type, double parameter)
      : name_(std::move(name)), type_(type), parameter_(parameter) {}
  std::string name_;
  const ObservableType* type_;
  double parameter_ = 0;
};

}  // namespace aggkit

#include "validation/observables/observable.hpp"

#include <limits>

namespace aggkit {

std::string describe_needs(unsigned needs) {
  static const std::pair<unsigned, const char*> names[] = {
      {need::sizes, "the size distribution"}, {need::leaked_mass, "the leaked mass"},
      {need::positions, "particle positions"}, {need::velocities, "particle velocities"},
      {need::masses, "particle masses"},       {need::clusters, "cluster labels"},
      {need::collisions, "collision counts"},  {need::virial, "the pair virial (periodic box)"}};
  std::string text;
  for (const auto& [bit, name] : names)
    if (needs & bit) text += (text.empty() ? "" : ", ") + std::string(name);
  return text.empty() ? "nothing" : text;
}

std::optional<Observable> Observable::from_name(std::string_view name) {
  for (const ObservableType& type : observable_types())
    if (const auto parameter = type.match(name)) return Observable(std::string(name), &type, *parameter);
  return std::nullopt;
}

std::string Observable::forms() {
  std::string text;
  for (const ObservableType& type : observable_types()) text += (text.empty() ? "" : ", ") + type.form;
  return "one of " + text;
}

double Observable::value(const ObservedState& state) const {
  if (type_->scalar) return type_->scalar(state, parameter_);
  if (type_->fit && state.particles()) return type_->fit(*state.particles()).dimension;
  return std::numeric_limits<double>::quiet_NaN();
}

std::vector<std::pair<std::string, double>> Observable::final_values(const ObservedState& state) const {
  if (!type_->fit) return {{name_, value(state)}};
  if (!state.particles()) return {{name_, std::numeric_limits<double>::quiet_NaN()}};
  const FractalFit f = type_->fit(*state.particles());
  return {{name_, f.dimension}, {name_ + "_error", f.standard_error}, {name_ + "_fit_min", f.fit_min},
          {name_ + "_fit_max", f.fit_max}};
}

std::string Observable::source() const {
  if (!is_series_measure()) return {};
  return name_.substr(name_.find(':') + 1);
}

Profile Observable::profile(const ParticleView& view) const { return type_->profile(view); }

}  // namespace aggkit

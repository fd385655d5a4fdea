#pragma once
// Observables a scene can ask for in `observe.series`:
//   M<p>        the moment M_p = Σ_k k^p n_k for a real p >= 0 (M0, M1, M2, M1.5, ...)
//   n<k>        the density n_k of size k (k >= 1)
//   mass_leak   the mass lost through the truncation so far (truncation = "drop")
//   clusters            the number of clusters (particle engines; NaN for densities)
//   kinetic_energy      Σ ½ m v² over the particles (particle engines; NaN for densities)
//   mean_cluster_size   particles per cluster; M1/M0 for densities
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "validation/observables/system_state.hpp"

namespace aggkit {

class Observable {
 public:
  enum class Kind { moment, density, mass_leak, clusters, kinetic_energy, mean_cluster_size };

  // The observable named `name`, or std::nullopt if the name is not one of the forms above.
  static std::optional<Observable> from_name(std::string_view name);
  static const char* forms();  // the allowed forms, for messages

  const std::string& name() const { return name_; }  // as written in the scene
  Kind kind() const { return kind_; }
  double order() const { return order_; }       // p of M<p>
  std::size_t size() const { return size_; }    // k of n<k>
  double evaluate(const SystemState& state) const;

 private:
  Observable(std::string name, Kind kind, double order, std::size_t size)
      : name_(std::move(name)), kind_(kind), order_(order), size_(size) {}
  std::string name_;
  Kind kind_;
  double order_ = 0.0;
  std::size_t size_ = 0;
};

}  // namespace aggkit

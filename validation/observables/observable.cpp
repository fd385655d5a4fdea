#include "validation/observables/observable.hpp"

#include <charconv>
#include <cmath>

namespace aggkit {

namespace {

// Parses all of `text` as a number of type T; std::nullopt unless the whole text is one number.
template <class T>
std::optional<T> parse_whole(std::string_view text) {
  T value{};
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  if (text.empty() || result.ec != std::errc() || result.ptr != end) return std::nullopt;
  return value;
}

}  // namespace

const char* Observable::forms() {
  return "M<p> with a real p >= 0 (M0, M1, M2, M1.5, ...), n<k> with an integer k >= 1 (n1, n10, ...), mass_leak, clusters, kinetic_energy or mean_cluster_size";
}

std::optional<Observable> Observable::from_name(std::string_view name) {
  if (name == "mass_leak") return Observable(std::string(name), Kind::mass_leak, 0.0, 0);
  if (name == "clusters") return Observable(std::string(name), Kind::clusters, 0.0, 0);
  if (name == "kinetic_energy") return Observable(std::string(name), Kind::kinetic_energy, 0.0, 0);
  if (name == "mean_cluster_size") return Observable(std::string(name), Kind::mean_cluster_size, 0.0, 0);
  if (name.size() < 2) return std::nullopt;
  const std::string_view rest = name.substr(1);
  if (name.front() == 'M') {
    // from_chars would also read "nan", "inf" and a sign: only plain decimal orders p >= 0 are allowed.
    if (!(std::isdigit(static_cast<unsigned char>(rest.front())) || rest.front() == '.')) return std::nullopt;
    const auto p = parse_whole<double>(rest);
    if (!p || !std::isfinite(*p) || *p < 0) return std::nullopt;
    return Observable(std::string(name), Kind::moment, *p, 0);
  }
  if (name.front() == 'n') {
    if (!std::isdigit(static_cast<unsigned char>(rest.front()))) return std::nullopt;
    const auto k = parse_whole<std::size_t>(rest);
    if (!k || *k < 1) return std::nullopt;
    return Observable(std::string(name), Kind::density, 0.0, *k);
  }
  return std::nullopt;
}

double Observable::evaluate(const SystemState& state) const {
  switch (kind_) {
    case Kind::moment: return state.moment(order_);
    case Kind::density: return state.density(size_);
    case Kind::mass_leak: return state.leaked_mass();
    case Kind::clusters: return state.clusters();
    case Kind::kinetic_energy: return state.kinetic_energy();
    case Kind::mean_cluster_size: return state.mean_cluster_size();
  }
  return 0.0;
}

}  // namespace aggkit

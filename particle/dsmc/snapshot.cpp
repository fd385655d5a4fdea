#include "particle/dsmc/snapshot.hpp"

#include <algorithm>
#include <cmath>

namespace aggkit::dsmc {

double Snapshot::moment(double p) const {
  // Neumaier-compensated sum [Neumaier1974], as analysis/moments.cpp does for densities.
  double sum = 0.0, compensation = 0.0;
  for (const auto& [size, count] : groups) {
    const double term = (p == 0.0 ? 1.0 : p == 1.0 ? double(size) : std::pow(double(size), p)) * double(count);
    const double t = sum + term;
    compensation += std::abs(sum) >= std::abs(term) ? (sum - t) + term : (term - t) + sum;
    sum = t;
  }
  return (sum + compensation) / volume;
}

double Snapshot::density(std::uint64_t k) const {
  const auto it = std::lower_bound(groups.begin(), groups.end(), std::pair<std::uint64_t, std::uint64_t>{k, 0});
  return it != groups.end() && it->first == k ? double(it->second) / volume : 0.0;
}

std::uint64_t Snapshot::mass() const {
  std::uint64_t m = 0;
  for (const auto& [size, count] : groups) m += size * count;
  return m;
}

}  // namespace aggkit::dsmc

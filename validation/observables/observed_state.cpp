#include "validation/observables/observed_state.hpp"

#include <algorithm>
#include <cmath>

#include "analysis/moments.hpp"
#include "solvers/discretisation.hpp"
#include "solvers/size_grid.hpp"

namespace aggkit {

double ObservedState::moment(double p) const { return aggkit::moment(distribution(), p); }

double ObservedState::density(std::size_t k) const {
  const std::vector<double> n = distribution();
  return k >= 1 && k <= n.size() ? n[k - 1] : 0.0;
}

double DensityState::moment(double p) const {
  if (sizes_.empty()) return aggkit::moment(n_, p);
  double sum = 0.0;
  for (std::size_t i = 0; i < n_.size(); ++i) sum += (p == 0.0 ? 1.0 : std::pow(sizes_[i], p)) * n_[i];
  return sum;
}

double DensityState::density(std::size_t k) const {
  if (sizes_.empty()) return k >= 1 && k <= n_.size() ? n_[k - 1] : 0.0;
  if (densities_.empty()) {
    if (grid_) {
      densities_ = grid_->densities(n_);
    } else {
      const std::vector<double> width = pivot_widths(sizes_);
      densities_.resize(n_.size());
      for (std::size_t i = 0; i < n_.size(); ++i) densities_[i] = n_[i] / width[i];
    }
  }
  return density_on_pivots(densities_, sizes_, double(k));
}

double density_on_pivots(std::span<const double> f, std::span<const double> sizes, double k) {
  if (sizes.empty() || k < sizes.front() || k > sizes.back()) return 0.0;
  const std::size_t i = std::size_t(std::lower_bound(sizes.begin(), sizes.end(), k) - sizes.begin());
  if (sizes[i] == k) return f[i];
  const double t = (k - sizes[i - 1]) / (sizes[i] - sizes[i - 1]), a = f[i - 1], b = f[i];
  if (a > 0.0 && b > 0.0) return a * std::exp(t * std::log(b / a));
  return a + t * (b - a);
}

}  // namespace aggkit

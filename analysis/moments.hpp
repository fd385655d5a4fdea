#pragma once
// Moments of a size distribution: M_p = Σ_k k^p n_k, with n[k-1] the density of size k.
#include <cstddef>
#include <span>
#include <vector>

namespace aggkit {

// Compensated sum [Neumaier1974] of k^p n_k over k = 1..n.size(); exact for the integer p = 0, 1 up to
// the round-off of one addition, so mass conservation can be checked to ~1e-15.
double moment(std::span<const double> n, double p);

// Several moments in one pass.
std::vector<double> moments(std::span<const double> n, std::span<const double> orders);

// Relative error |value - reference| / |reference| (absolute error where the reference is 0).
double relative_error(double value, double reference);

}  // namespace aggkit

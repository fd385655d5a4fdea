#include "solvers/poincare_section.hpp"

#include <cmath>

namespace aggkit {

bool UpwardCrossings::add(double t, std::span<const double> n) {
  double m0 = 0.0;
  for (double v : n) m0 += v;
  t_.push_back(t);
  m0_.push_back(m0);
  if (keep_states_) n_.emplace_back(n.begin(), n.end());
  if (t_.size() > 4) {
    t_.pop_front();
    m0_.pop_front();
    if (keep_states_) n_.pop_front();
  }
  bool found = false;
  if (pending_ && t_.size() == 4) {
    interpolate(1, 2);
    found = true;
  }
  pending_ = false;
  const std::size_t i = t_.size() - 1;
  if (i >= 1 && m0_[i - 1] < level_ && m0 >= level_) {
    if (i >= 2) {
      pending_ = true;  // the cubic through two samples each side, once the next step is taken
    } else {
      interpolate(0, 1);
      found = true;
    }
  }
  return found;
}

void UpwardCrossings::interpolate(std::size_t low, std::size_t high) {
  const std::size_t samples = t_.size();
  // Lagrange weights at s of the samples (a straight line through two, the cubic through four).
  const auto weights = [&](double s) {
    std::vector<double> w(samples, 1.0);
    for (std::size_t i = 0; i < samples; ++i)
      for (std::size_t j = 0; j < samples; ++j)
        if (j != i) w[i] *= (s - t_[j]) / (t_[i] - t_[j]);
    return w;
  };
  const auto m0_at = [&](double s) {
    const std::vector<double> w = weights(s);
    double value = 0.0;
    for (std::size_t i = 0; i < samples; ++i) value += w[i] * m0_[i];
    return value;
  };
  double below = t_[low], above = t_[high];
  for (int k = 0; k < 60 && above - below > 1e-15 * std::abs(above); ++k) {
    const double mid = 0.5 * (below + above);
    (m0_at(mid) < level_ ? below : above) = mid;
  }
  time_ = 0.5 * (below + above);
  if (!keep_states_) return;
  const std::vector<double> w = weights(time_);
  state_.assign(n_.front().size(), 0.0);
  for (std::size_t i = 0; i < samples; ++i)
    for (std::size_t k = 0; k < state_.size(); ++k) state_[k] += w[i] * n_[i][k];
}

}  // namespace aggkit

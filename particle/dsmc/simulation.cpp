#include "particle/dsmc/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "analysis/input_error.hpp"
#include "particle/dsmc/acceptance_rejection.hpp"
#include "particle/dsmc/fast_dsmc.hpp"

namespace aggkit::dsmc {

namespace {
// Under a cutoff the majorant cannot see that every present pair is forbidden; after this many rejected
// trials in a row the population is checked exactly.
constexpr std::uint64_t rejection_watchdog = 1u << 20;
}  // namespace

std::vector<std::uint64_t> initial_counts(const std::vector<double>& n, std::uint64_t particles) {
  const double total = std::accumulate(n.begin(), n.end(), 0.0);
  std::vector<std::uint64_t> counts(n.size(), 0);
  std::vector<std::pair<double, std::size_t>> remainders;
  std::uint64_t assigned = 0;
  for (std::size_t k = 0; k < n.size(); ++k) {
    const double exact = n[k] / total * double(particles);
    counts[k] = std::uint64_t(std::floor(exact));
    assigned += counts[k];
    remainders.push_back({exact - double(counts[k]), k});
  }
  std::stable_sort(remainders.begin(), remainders.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t i = 0; assigned < particles && i < remainders.size(); ++i, ++assigned) ++counts[remainders[i].second];
  return counts;
}

Simulation::Simulation(const AggregationModel& model, const Options& options, std::uint64_t seed, double t_end)
    : model_(model), options_(options), random_(seed) {
  options_.validate();
  model_.validate(t_end);
  const InteractionKernel kernel(model_.kernel, options_.truncate, model_.truncation, model_.size);
  if (options_.method == Method::fast)
    stepper_ = std::make_unique<FastDsmc>(kernel, options_.bucket);
  else
    stepper_ = std::make_unique<AcceptanceRejection>(kernel, options_.bucket);
  const std::vector<std::uint64_t> counts = initial_counts(model_.initial, options_.particles);
  double density = 0.0;
  for (std::size_t k = 0; k < counts.size(); ++k) {
    stepper_->add(k + 1, counts[k]);
    initial_mass_ += (k + 1) * counts[k];
    density += model_.initial[k];
  }
  initial_particles_ = options_.particles;
  lambda_is_constant_ = model_.lambda.is_constant();
  constant_lambda_ = model_.lambda(0.0);
  control_mass_ = initial_mass_;
  volume_ = double(options_.particles) / density;
}

std::uint64_t Simulation::mass() const {
  std::uint64_t m = stepper_->leaked_mass();
  stepper_->for_each_group([&](std::uint64_t size, std::uint64_t count) { m += size * count; });
  return m;
}

bool Simulation::no_pair_can_interact() const {
  if (stepper_->particles() < 2) return true;
  const std::uint64_t cutoff = options_.truncate && model_.truncation == Truncation::cutoff ? model_.size : 0;
  if (cutoff == 0) return false;
  std::uint64_t smallest = std::numeric_limits<std::uint64_t>::max(), second = smallest;
  stepper_->for_each_group([&](std::uint64_t size, std::uint64_t count) {
    for (std::uint64_t c = 0; c < std::min<std::uint64_t>(count, 2); ++c) {
      if (size < smallest) {
        second = smallest;
        smallest = size;
      } else if (size < second) {
        second = size;
      }
    }
  });
  return smallest + second > cutoff;
}

void Simulation::freeze() {
  statistics_.frozen = true;
  statistics_.extinct = stepper_->particles() < 2;
  statistics_.frozen_time = time_;
  next_trial_ = std::numeric_limits<double>::infinity();
}

void Simulation::advance_to(double t, const std::function<void(double time)>& every) {
  if (t < time_) throw std::invalid_argument("dsmc: advance_to a time before the current one");
  // The acceptance-rejection stepper is a final class: its trials are called directly, not through the
  // Stepper interface (three indirect calls per trial of ~100 ns).
  if (auto* stepper = dynamic_cast<AcceptanceRejection*>(stepper_.get()))
    run_trials(*stepper, t, every);
  else
    run_trials(*stepper_, t, every);
}

template <class StepperType>
void Simulation::run_trials(StepperType& stepper, double t, const std::function<void(double time)>& every) {
  while (true) {
    if (every && (statistics_.trials & ((std::uint64_t(1) << 20) - 1)) == 0 && statistics_.trials > 0) every(time_);
    if (next_trial_ < time_) {
      const double weight = stepper.particles() < 2 ? 0.0 : stepper.trial_weight();
      if (!(weight > 0.0)) {
        freeze();
        break;
      }
      next_lambda_ = lambda_is_constant_ ? constant_lambda_ : model_.lambda(time_);
      if (weight != step_.weight || volume_ != step_.volume || next_lambda_ != step_.lambda)
        step_ = {weight, volume_, next_lambda_, 2.0 * volume_ / ((1.0 + next_lambda_) * weight)};
      next_trial_ = time_ + step_.step;
    }
    if (next_trial_ > t) break;
    time_ = next_trial_;
    ++statistics_.trials;
    const TrialOutcome outcome = stepper.trial(next_lambda_, random_);
    next_trial_ = -1.0;
    switch (outcome) {
      case TrialOutcome::rejected:
        if (++rejections_in_a_row_ >= rejection_watchdog) {
          rejections_in_a_row_ = 0;
          if (no_pair_can_interact()) freeze();
        }
        continue;
      case TrialOutcome::aggregated: ++statistics_.aggregations; break;
      case TrialOutcome::shattered: ++statistics_.shatterings; break;
      case TrialOutcome::leaked: ++statistics_.leaks; break;
    }
    rejections_in_a_row_ = 0;
    if (options_.population_control && 2 * stepper.particles() < initial_particles_) {
      stepper.duplicate();
      volume_ *= 2.0;
      ++statistics_.doublings;
      control_mass_ *= 2;
    } else if (options_.population_control && options_.population_halving &&
               stepper.particles() > 2 * initial_particles_) {
      stepper.halve(random_);
      volume_ *= 0.5;
      ++statistics_.halvings;
      control_mass_ = mass();
    }
  }
  time_ = std::max(time_, t);
}

Snapshot Simulation::snapshot() const {
  Snapshot s;
  s.time = time_;
  s.volume = volume_;
  s.particles = stepper_->particles();
  s.leaked_mass = stepper_->leaked_mass();
  stepper_->for_each_group([&](std::uint64_t size, std::uint64_t count) { s.groups.push_back({size, count}); });
  std::sort(s.groups.begin(), s.groups.end());
  // Merge individually stored particles of equal size.
  std::size_t out = 0;
  for (std::size_t i = 0; i < s.groups.size(); ++i) {
    if (out > 0 && s.groups[out - 1].first == s.groups[i].first)
      s.groups[out - 1].second += s.groups[i].second;
    else
      s.groups[out++] = s.groups[i];
  }
  s.groups.resize(out);
  return s;
}

}  // namespace aggkit::dsmc

#include "validation/validate/job_slots.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace aggkit {

SlotScheduler::SlotScheduler(std::vector<SlotDemand> jobs, std::size_t slots)
    : jobs_(std::move(jobs)), order_(jobs_.size()), held_(jobs_.size(), 0), free_(std::max<std::size_t>(slots, 1)) {
  std::iota(order_.begin(), order_.end(), std::size_t(0));
  std::stable_sort(order_.begin(), order_.end(),
                   [&](std::size_t x, std::size_t y) { return jobs_[x].priority > jobs_[y].priority; });
}

std::optional<SlotScheduler::Start> SlotScheduler::next() {
  if (all_started() || free_ == 0) return std::nullopt;
  const std::size_t job = order_[next_++];
  const std::size_t slots = std::min(std::max<std::size_t>(jobs_[job].max_slots, 1), free_);
  held_[job] = slots;
  free_ -= slots;
  return Start{job, slots};
}

void SlotScheduler::finished(std::size_t job) {
  if (held_.at(job) == 0) throw std::logic_error("SlotScheduler::finished: job " + std::to_string(job) + " holds no slots");
  free_ += held_[job];
  held_[job] = 0;
}

}  // namespace aggkit

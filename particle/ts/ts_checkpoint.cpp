// TimeSteppingAggregation::save and restore (time_stepping_aggregation.hpp).
#include <algorithm>

#include "particle/common/checkpoint.hpp"
#include "particle/ts/time_stepping_aggregation.hpp"

namespace aggkit {

void TimeSteppingAggregation::save(StateWriter& out) const {
  sync_all();  // the logged quiet flights applied (the same positions as applied flights would give)
  out.put(std::uint64_t(x_.size()));
  members_.save(out);
  cells_.save(out);
  out.put(x_);
  out.put(velocity_);
  out.put(flown_);
  out.put(reflected_);
  out.put(reflected_list_);
  out.put(longest_flight_);
  out.put(speed_);
  out.put(safe_left_);
  out.put(std::uint8_t(jumped_));
  for (const auto& partners : links_) out.put(partners);
  out.put(nearest_);
  out.put(time_);
  out.put(wall_impulse_);
  out.put(counters_);
  out.put(last_mean_);
}

void TimeSteppingAggregation::restore(StateReader& in) {
  const std::size_t n = x_.size();
  in.expect(std::uint64_t(n), "number of TS particles");
  members_.restore(in);
  cells_.restore(in);
  in.get(x_);
  in.get(velocity_);
  in.get(flown_);
  in.get(reflected_);
  in.get(reflected_list_);
  in.get(longest_flight_);
  in.get(speed_);
  in.get(safe_left_);
  jumped_ = in.read<std::uint8_t>() != 0;
  for (auto& partners : links_) {
    in.get(partners);
    for (std::uint32_t j : partners)
      if (j >= n) throw CheckpointError("the checkpoint's TS links name a particle beyond the count");
  }
  in.get(nearest_);
  in.get(time_);
  in.get(wall_impulse_);
  in.get(counters_);
  in.get(last_mean_);
  logged_.clear();
  partial_.clear();
  std::fill(applied_.begin(), applied_.end(), 0u);
  extents_ = false;
  live_stale_ = true;
  if (x_.size() != n || velocity_.size() != n || flown_.size() != n || reflected_.size() != n)
    throw CheckpointError("the checkpoint's TS configuration has another number of particles");
}

}  // namespace aggkit

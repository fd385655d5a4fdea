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
  out.put(expires_);
  out.put(near_key_);
  out.put(rate_);
  out.put(checked_pass_);
  out.put(changed_);
  out.put(passes_);
  out.put(clock_);
  out.put(std::uint8_t(bounds_));
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
  in.get(expires_);
  in.get(near_key_);
  in.get(rate_);
  in.get(checked_pass_);
  in.get(changed_);
  in.get(passes_);
  in.get(clock_);
  bounds_ = in.read<std::uint8_t>() != 0;
  in.get(time_);
  in.get(wall_impulse_);
  in.get(counters_);
  in.get(last_mean_);
  logged_.clear();
  partial_.clear();
  std::fill(applied_.begin(), applied_.end(), 0u);
  extents_ = false;
  live_stale_ = true;
  if (x_.size() != n || velocity_.size() != n || flown_.size() != n || reflected_.size() != n || expires_.size() != n ||
      near_key_.size() != n || rate_.size() != n || checked_pass_.size() != n || changed_.size() != n)
    throw CheckpointError("the checkpoint's TS configuration has another number of particles");
}

}  // namespace aggkit

// TimeSteppingAggregation::save and restore (time_stepping_aggregation.hpp).

#include "particle/common/checkpoint.hpp"
#include "particle/ts/time_stepping_aggregation.hpp"

namespace aggkit {

void TimeSteppingAggregation::save(StateWriter& out) const {
  sync_all();  // the logged quiet flights applied (the same positions as applied flights would give)
  out.put(std::uint64_t(particles()));
  members_.save(out);
  cells_.save(out);
  out.put(flights_.x);
  out.put(velocity_);
  out.put(flights_.flown);
  out.put(reflected_);
  out.put(reflected_list_);
  out.put(longest_flight_);
  out.put(speed_);
  out.put(safe_left_);
  out.put(std::uint8_t(jumped_));
  for (const auto& partners : links_) out.put(partners);
  detection_.save(out);
  out.put(time_);
  out.put(wall_impulse_);
  out.put(counters_);
  out.put(last_mean_);
}

void TimeSteppingAggregation::restore(StateReader& in) {
  const std::size_t n = particles();
  in.expect(std::uint64_t(n), "number of TS particles");
  members_.restore(in);
  cells_.restore(in);
  in.get(flights_.x);
  in.get(velocity_);
  in.get(flights_.flown);
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
  detection_.restore(in);
  in.get(time_);
  in.get(wall_impulse_);
  in.get(counters_);
  in.get(last_mean_);
  flights_.forget_log();
  if (flights_.x.size() != n || velocity_.size() != n || flights_.flown.size() != n || reflected_.size() != n)
    throw CheckpointError("the checkpoint's TS configuration has another number of particles");
  live_stale_ = true;
  refresh_live();
}

}  // namespace aggkit

// Dem::save and Dem::restore: the state step() carries from step to step (dem.hpp).
#include "particle/common/checkpoint.hpp"
#include "particle/dem/dem.hpp"

namespace aggkit {

void Dem::save(StateWriter& out) const {
  out.put(std::uint64_t(x_.size()));
  out.put(x_);
  out.put(v_);
  out.put(f_);
  out.put(gravity_);
  out.put(u_);
  out.put(time_);
  out.put(wall_impulse_);
  out.put(wall_force_);
  out.put(counters_);
  out.put(w_);
  out.put(w_pred_);
  out.put(torque_);
  out.put(q_);
  out.put(pairs_.first);
  out.put(pairs_.second);
  out.put(pairs_.state);
  out.put(pairs_.history);
  out.put(pairs_built_at_);
  out.put(graph_edges_);
  out.put(std::uint8_t(first_evaluation_));
  out.put(std::uint8_t(moved_beyond_skin_));
  out.put(std::uint8_t(forces_cleared_));
}

void Dem::restore(StateReader& in) {
  in.expect(std::uint64_t(x_.size()), "number of DEM particles");
  const auto same_size = [](const auto& a, const auto& b, const char* what) {
    if (a.size() != b.size()) throw CheckpointError(std::string("the checkpoint's DEM ") + what + " has another length");
  };
  const std::vector<Vector3> x = x_, w = w_;
  const std::vector<std::array<double, 4>> q = q_;
  in.get(x_);
  same_size(x_, x, "positions");
  in.get(v_);
  same_size(v_, x, "velocities");
  in.get(f_);
  same_size(f_, x, "forces");
  in.get(gravity_);
  in.get(u_);
  in.get(time_);
  in.get(wall_impulse_);
  in.get(wall_force_);
  in.get(counters_);
  in.get(w_);
  same_size(w_, w, "angular velocities");
  in.get(w_pred_);
  in.get(torque_);
  in.get(q_);
  same_size(q_, q, "orientations");
  in.get(pairs_.first);
  in.get(pairs_.second);
  in.get(pairs_.state);
  in.get(pairs_.history);
  if (pairs_.second.size() != pairs_.first.size() || pairs_.state.size() != pairs_.first.size() ||
      (!pairs_.history.empty() && pairs_.history.size() != pairs_.first.size()))
    throw CheckpointError("the checkpoint's DEM pair list has lists of different lengths");
  for (std::size_t k = 0; k < pairs_.first.size(); ++k)
    if (pairs_.first[k] >= x_.size() || pairs_.second[k] >= x_.size())
      throw CheckpointError("the checkpoint's DEM pair list names a particle beyond the count");
  in.get(pairs_built_at_);
  in.get(graph_edges_);
  first_evaluation_ = in.read<std::uint8_t>() != 0;
  moved_beyond_skin_ = in.read<std::uint8_t>() != 0;
  forces_cleared_ = in.read<std::uint8_t>() != 0;
}

}  // namespace aggkit

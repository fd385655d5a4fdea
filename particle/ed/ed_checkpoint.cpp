// Checkpoints of event-driven aggregation: save and restore of the broad phase and of the run
// (event_driven_aggregation.hpp).
#include "particle/ed/cluster_index.hpp"
#include "particle/ed/event_driven_aggregation.hpp"
#include "particle/ed/hierarchical_grid.hpp"

namespace aggkit {

void HierarchicalGrid::save(StateWriter& out) const {
  out.put(std::uint64_t(cells_.size()));
  for (const auto& level : cells_) {
    out.put(std::uint64_t(level.size()));
    for (const Cell& cell : level) {
      out.put(cell.owners);
      out.put(cell.passengers);
    }
  }
  out.put(range_);
  out.put(where_);
}

void HierarchicalGrid::restore(StateReader& in) {
  in.expect(std::uint64_t(cells_.size()), "number of broad-phase levels");
  for (auto& level : cells_) {
    in.expect(std::uint64_t(level.size()), "number of broad-phase cells");
    for (Cell& cell : level) {
      in.get(cell.owners);
      in.get(cell.passengers);
    }
  }
  in.get(range_);
  in.get(where_);
}

void ClusterIndex::save(StateWriter& out) const {
  out.put(slots_);
  out.put(std::uint64_t(used_));
  out.put(next_);
}

void ClusterIndex::restore(StateReader& in) {
  const std::size_t particles = next_.size();
  in.get(slots_);
  used_ = std::size_t(in.read<std::uint64_t>());
  in.get(next_);
  if (next_.size() != particles || slots_.empty() || used_ > slots_.size())
    throw CheckpointError("the checkpoint's cluster index does not fit this run");
  refilter();
}

void EventDrivenAggregation::save(StateWriter& out) const {
  out.put(std::uint64_t(offset_.size()));
  members_.save(out);
  index_.save(out);
  grid_.save(out);
  out.put(offset_);
  out.put(origin_);
  out.put(velocity_);
  out.put(low_);
  out.put(high_);
  out.put(clock_);
  out.put(stamp_);
  out.put(level_);
  out.put(alive_);
  out.put(alive_at_);
  out.put(top_);
  out.put(top_at_);
  out.put(seen_);
  out.put(epoch_);
  out.put(next_stamp_);
  queue_.save(out);
  out.put(std::uint64_t(compact_at_));
  out.put(populated_);
  out.put(raises_);
  out.put(now_);
  out.put(clock_origin_);
  out.put(wall_impulse_);
  out.put(counters_);
}

void EventDrivenAggregation::restore(StateReader& in) {
  const std::size_t n = offset_.size();
  in.expect(std::uint64_t(n), "number of ED particles");
  members_.restore(in);
  index_.restore(in);
  grid_.restore(in);
  in.get(offset_);
  in.get(origin_);
  in.get(velocity_);
  in.get(low_);
  in.get(high_);
  in.get(clock_);
  in.get(stamp_);
  in.get(level_);
  in.get(alive_);
  in.get(alive_at_);
  in.get(top_);
  in.get(top_at_);
  in.get(seen_);
  in.get(epoch_);
  in.get(next_stamp_);
  queue_.restore(in);
  compact_at_ = std::size_t(in.read<std::uint64_t>());
  in.get(populated_);
  in.get(raises_);
  in.get(now_);
  in.get(clock_origin_);
  in.get(wall_impulse_);
  in.get(counters_);
  if (offset_.size() != n || origin_.size() != n || velocity_.size() != n || clock_.size() != n || stamp_.size() != n)
    throw CheckpointError("the checkpoint's ED state has another number of particles or clusters");
}

}  // namespace aggkit

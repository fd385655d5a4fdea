// Broad phase of the ED engine: clusters' inflated bounding boxes registered in the hierarchical grid,
// the candidate relation, and the enumeration of a cluster's candidates after its velocity changed.
#include "particle/ed/event_driven_aggregation.hpp"

namespace aggkit {

Vector3 EventDrivenAggregation::extent(std::uint32_t c) const {
  const double pad = 2 * (radius_ + margin_);
  return {high_[c][0] - low_[c][0] + pad, high_[c][1] - low_[c][1] + pad, high_[c][2] - low_[c][2] + pad};
}

int EventDrivenAggregation::passenger_top(std::uint32_t c) const {
  return std::min(grid_.top() - 1, std::max(level_[c], populated_));
}

void EventDrivenAggregation::register_cluster(std::uint32_t c) {
  level_[c] = grid_.level_for(extent(c));
  if (level_[c] == grid_.top()) {
    top_at_[c] = std::uint32_t(top_.size());
    top_.push_back(c);
    return;
  }
  if (level_[c] > populated_) raise_populated(level_[c], c);
  const Vector3 origin = cluster_origin(c);
  const double pad = radius_ + margin_;
  Vector3 lo{0, 0, 0}, hi{0, 0, 0};
  for (int a = 0; a < box_.dimension; ++a) {
    lo[a] = origin[a] + low_[c][a] - pad;
    hi[a] = origin[a] + high_[c][a] + pad;
  }
  for (int l = level_[c]; l <= passenger_top(c); ++l) grid_.place(c, l, grid_.range_of(l, lo, hi), l == level_[c]);
}

void EventDrivenAggregation::raise_populated(int level, std::uint32_t except) {
  const int from = populated_ + 1;
  populated_ = level;
  ++raises_;
  const double pad = radius_ + margin_;
  for (const std::uint32_t c : alive_) {
    if (c == except || level_[c] >= level) continue;  // the top's clusters included
    const Vector3 origin = cluster_origin(c);
    Vector3 lo{0, 0, 0}, hi{0, 0, 0};
    for (int a = 0; a < box_.dimension; ++a) {
      lo[a] = origin[a] + low_[c][a] - pad;
      hi[a] = origin[a] + high_[c][a] + pad;
    }
    for (int l = std::max(from, level_[c] + 1); l <= level; ++l) grid_.place(c, l, grid_.range_of(l, lo, hi), false);
    predict_crossing(c);
  }
}

void EventDrivenAggregation::unregister_cluster(std::uint32_t c) {
  if (level_[c] == grid_.top()) {
    const std::uint32_t at = top_at_[c], moved = top_.back();
    top_[at] = moved;
    top_at_[moved] = at;
    top_.pop_back();
    return;
  }
  for (int l = level_[c]; l <= passenger_top(c); ++l) grid_.remove(c, l, l == level_[c]);
}

bool EventDrivenAggregation::candidates(std::uint32_t x, std::uint32_t y) const {
  const int m = std::max(level_[x], level_[y]);
  if (m == grid_.top()) return true;
  return grid_.share_cell(m, grid_.range(x, m), grid_.range(y, m));
}

// Every candidate of `c` (once each): at c's own level everything in its cells, at coarser levels the
// clusters that live there, and the top-level clusters; all live clusters if c is itself at the top.
void EventDrivenAggregation::predict_cluster(std::uint32_t c, bool higher_only) {
  predict_wall(c);
  predict_crossing(c);
  ++epoch_;
  seen_[c] = epoch_;
  auto visit = [&](std::uint32_t y) {
    if (seen_[y] == epoch_) return;
    seen_[y] = epoch_;
    if (higher_only && y < c) return;
    predict_pair(c, y);
  };
  if (level_[c] == grid_.top()) {
    for (std::uint32_t y : alive_) visit(y);
    return;
  }
  std::array<std::uint32_t, 8> cells;
  for (int l = level_[c]; l <= passenger_top(c); ++l) {
    const int n = grid_.cells(l, grid_.range(c, l), cells);
    for (int k = 0; k < n; ++k) {
      for (const auto& e : grid_.owners(l, cells[k])) visit(e.cluster);
      if (l == level_[c])
        for (const auto& e : grid_.passengers(l, cells[k])) visit(e.cluster);
    }
  }
  for (std::uint32_t y : top_) visit(y);
}

}  // namespace aggkit

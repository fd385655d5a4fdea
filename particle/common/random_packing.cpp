#include "particle/common/random_packing.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <stdexcept>

#include "particle/common/cell_grid.hpp"
#include "particle/common/cell_list.hpp"

namespace aggkit {

namespace {

// The box whose cell grid holds the particles, with the world position of its corner: a periodic box
// itself (images matter), otherwise a walled box around the region (or around the given positions).
struct Frame {
  Box box;
  Vector3 origin{0, 0, 0};
};

Frame cube_frame(int dimension, const Vector3& low, double side) {
  Frame frame;
  frame.box = Box{dimension, {side, side, dimension == 3 ? side : 0.0}, Boundary::reflecting};
  frame.origin = low;
  if (dimension == 2) frame.origin[2] = 0;
  return frame;
}

// Particles placed so far, on a cell grid of cells at least one contact distance wide.
class ContactGrid {
 public:
  ContactGrid(const Frame& frame, double contact, std::size_t count)
      : frame_(frame), grid_(frame.box, contact, count), cells_(grid_.size(), count), positions_(count), radii_(count) {}

  // A placed particle that `x` (world coordinates) with radius r comes closer to than factor·(r + R_p).
  std::optional<std::uint32_t> overlapping(const Vector3& x, double r, double factor) const {
    const Vector3 local = x - frame_.origin;
    const CellCoords c = grid_.coords_of(local);
    for (const CellCoords& offset : grid_.stencil()) {
      const std::optional<CellCoords> n = grid_.neighbour(c, offset);
      if (!n) continue;
      for (std::uint32_t p = cells_.first(grid_.index(*n)); p != CellList::none; p = cells_.next(p)) {
        const Vector3 d = frame_.box.minimum_image(positions_[p] - local);
        const double reach = factor * (r + radii_[p]);
        if (dot(d, d) < reach * reach) return p;
      }
    }
    return std::nullopt;
  }

  void insert(std::uint32_t p, const Vector3& x, double r) {
    positions_[p] = x - frame_.origin;
    radii_[p] = r;
    cells_.insert(p, grid_.index(grid_.coords_of(positions_[p])));
  }

 private:
  Frame frame_;
  CellGrid grid_;
  CellList cells_;
  std::vector<Vector3> positions_;  // frame coordinates
  std::vector<double> radii_;
};

double largest(std::span<const double> radii) {
  double r = 0;
  for (double x : radii) r = std::max(r, x);
  return r;
}

}  // namespace

double PackingRegion::volume(int dimension) const {
  const double s = size;
  switch (shape) {
    case Shape::whole_box: break;
    case Shape::cube: return dimension == 2 ? s * s : s * s * s;
    case Shape::sphere: return dimension == 2 ? std::numbers::pi * s * s / 4 : std::numbers::pi * s * s * s / 6;
  }
  throw std::logic_error("PackingRegion::volume: the whole box has the box's volume");
}

Packing random_sequential_addition(const Box& box, const PackingRegion& region, std::span<const double> radii,
                                   std::uint64_t seed, std::size_t attempts_per_particle) {
  box.validate();
  const int dimension = box.dimension;
  const bool periodic = box.boundary == Boundary::periodic;
  if (region.shape == PackingRegion::Shape::whole_box && box.boundary == Boundary::open)
    throw std::invalid_argument("random_sequential_addition: open space has no whole box to fill");
  Packing packing;
  packing.count = radii.size();
  packing.positions.assign(radii.size(), Vector3{0, 0, 0});
  if (radii.empty()) return packing;
  if (radii.size() >= CellList::none) throw std::invalid_argument("random_sequential_addition: too many particles");
  const double contact = 2 * largest(radii);

  Frame frame;
  if (periodic || region.shape == PackingRegion::Shape::whole_box) {
    frame.box = box;
  } else {
    Vector3 low = region.centre;
    for (int a = 0; a < dimension; ++a) low[a] -= region.size / 2;
    frame = cube_frame(dimension, low, region.size);
  }
  ContactGrid placed(frame, contact, radii.size());

  // Larger particles first; equal radii keep their order.
  std::vector<std::uint32_t> order(radii.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return radii[a] > radii[b]; });

  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // A uniformly random centre for a particle of radius r with the whole particle inside the region (anywhere
  // in a periodic box); false when no such centre exists.
  const auto trial = [&](double r, Vector3& x) {
    x = {0, 0, 0};
    switch (region.shape) {
      case PackingRegion::Shape::whole_box:
        for (int a = 0; a < dimension; ++a) {
          const double width = periodic ? box.side[a] : box.side[a] - 2 * r;
          if (!(width > 0)) return false;
          x[a] = (periodic ? 0.0 : r) + width * unit(rng);
        }
        return true;
      case PackingRegion::Shape::cube: {
        const double width = region.size - 2 * r;
        if (!(width > 0)) return false;
        for (int a = 0; a < dimension; ++a) x[a] = region.centre[a] - width / 2 + width * unit(rng);
        return true;
      }
      case PackingRegion::Shape::sphere: {
        const double reach = region.size / 2 - r;  // the centre's ball
        if (!(reach > 0)) return false;
        Vector3 y;
        do {
          y = {0, 0, 0};
          for (int a = 0; a < dimension; ++a) y[a] = reach * (2 * unit(rng) - 1);
        } while (dot(y, y) > reach * reach);
        x = region.centre + y;
        if (dimension == 2) x[2] = 0;
        return true;
      }
    }
    return false;
  };

  for (const std::uint32_t p : order) {
    const double r = radii[p];
    bool done = false;
    Vector3 x;
    for (std::size_t attempt = 0; attempt < attempts_per_particle && !done; ++attempt) {
      if (!trial(r, x)) break;
      ++packing.attempts;
      done = !placed.overlapping(x, r, 1.0);
    }
    if (!done) return packing;
    placed.insert(p, x, r);
    packing.positions[p] = x;
    ++packing.placed;
  }
  return packing;
}

std::optional<std::pair<std::size_t, std::size_t>> first_overlap(const Box& box, std::span<const Vector3> positions,
                                                                 std::span<const double> radii, double tolerance) {
  if (radii.size() != positions.size()) throw std::invalid_argument("first_overlap: one radius per position");
  if (positions.empty()) return std::nullopt;
  const double contact = 2 * largest(radii);
  Frame frame;
  if (box.boundary == Boundary::open) {
    // A walled frame around the particles, padded by a contact distance.
    Vector3 low = positions[0], high = positions[0];
    for (const Vector3& x : positions)
      for (int a = 0; a < box.dimension; ++a) {
        low[a] = std::min(low[a], x[a]);
        high[a] = std::max(high[a], x[a]);
      }
    double side = 0;
    for (int a = 0; a < box.dimension; ++a) {
      low[a] -= contact;
      side = std::max(side, high[a] - low[a] + contact);
    }
    frame = cube_frame(box.dimension, low, side);
  } else {
    frame.box = box;
  }
  ContactGrid placed(frame, contact, positions.size());
  for (std::size_t j = 0; j < positions.size(); ++j) {
    if (const auto i = placed.overlapping(positions[j], radii[j], 1 - tolerance)) return std::make_pair(std::size_t(*i), j);
    placed.insert(std::uint32_t(j), positions[j], radii[j]);
  }
  return std::nullopt;
}

}  // namespace aggkit

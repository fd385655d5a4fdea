// Cell grids and lists: cell sizes, neighbours across periodic faces and walls, list membership.
#include <catch2/catch.hpp>
#include <set>

#include "analysis/input_error.hpp"
#include "particle/common/cell_grid.hpp"
#include "particle/common/cell_list.hpp"

using namespace aggkit;

TEST_CASE("cells are at least the contact distance and about the wanted number", "[particle_common][cells]") {
  const CellGrid dense(Box{2, {10, 10, 0}, Boundary::periodic}, 1.0, 10000);
  CHECK(dense.counts()[0] == 10);  // limited by the minimum side 1
  const CellGrid sparse(Box{2, {100, 100, 0}, Boundary::periodic}, 1.0, 100);
  CHECK(sparse.counts()[0] == 10);  // (10^4/100)^{1/2} = 10 wide
  CHECK(sparse.cell_side()[0] == Approx(10));
  CHECK(sparse.stencil().size() == 9);
  const CellGrid cube(Box{3, {10, 10, 10}, Boundary::reflecting}, 1.0, 1000);
  CHECK(cube.stencil().size() == 27);
  CHECK(cube.size() == 1000);
  CHECK_THROWS_AS(CellGrid(Box{2, {2.5, 10, 0}, Boundary::periodic}, 1.0, 10), InputError);
}

TEST_CASE("neighbours wrap across periodic faces and stop at walls", "[particle_common][cells]") {
  const CellGrid periodic(Box{2, {10, 10, 0}, Boundary::periodic}, 1.0, 100);
  CHECK(periodic.neighbour({0, 9, 0}, {-1, 1, 0}) == CellCoords{9, 0, 0});
  std::set<std::size_t> distinct;
  for (const auto& o : periodic.stencil()) distinct.insert(periodic.index(*periodic.neighbour({0, 0, 0}, o)));
  CHECK(distinct.size() == 9);
  const CellGrid walls(Box{2, {10, 10, 0}, Boundary::reflecting}, 1.0, 100);
  CHECK_FALSE(walls.neighbour({0, 5, 0}, {-1, 0, 0}));
  CHECK(walls.coords_of({9.999, 0.5, 0}) == CellCoords{9, 0, 0});
  CHECK(walls.coords(walls.index({3, 7, 0})) == CellCoords{3, 7, 0});
}

TEST_CASE("cell lists insert, move and remove", "[particle_common][cells]") {
  CellList list(4, 3);
  list.insert(0, 1);
  list.insert(1, 1);
  list.insert(2, 3);
  std::set<std::uint32_t> in1;
  for (auto p = list.first(1); p != CellList::none; p = list.next(p)) in1.insert(p);
  CHECK(in1 == std::set<std::uint32_t>{0, 1});
  list.move(1, 3);
  CHECK(list.first(1) == 0);
  CHECK(list.next(0) == CellList::none);
  CHECK(list.cell_of(1) == 3);
  list.remove(0);
  CHECK(list.first(1) == CellList::none);
}

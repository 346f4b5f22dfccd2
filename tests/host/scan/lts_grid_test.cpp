// The LTS filter's grid: each point's windows, its line sides along the rows, columns and
// diagonals (nearest first, ending at a gap or after kLineReach points); and points that form no
// grid.
#include "host/scan/lts_grid.h"

#include <CppUTest/TestHarness.h>

#include <vector>

using dg::host::Point3;
using dg::host::lts::grid_neighbourhoods;
using dg::host::lts::kLineReach;
using dg::host::lts::LineSides;
using dg::host::lts::WindowLists;

namespace {

// An nx x ny grid at 0.5 mm, row by row, without the cells `hole` names (x + nx y).
std::vector<Point3> grid(int nx, int ny, std::vector<int> holes = {}) {
  std::vector<Point3> out;
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      bool hole = false;
      for (int h : holes) hole = hole || h == x + nx * y;
      if (!hole) out.push_back({0.5 * x, 0.5 * y, 0.01 * x});
    }
  }
  return out;
}

size_t index_at(const std::vector<Point3>& points, double x, double y) {
  for (size_t i = 0; i < points.size(); ++i) {
    if (points[i].x == x && points[i].y == y) return i;
  }
  FAIL("no such point");
  return 0;
}

}  // namespace

TEST_GROUP(LtsGrid){};

// Sides 0 and 1 run along -x and +x, 2 and 3 along -y and +y (lts_grid.cpp's order).
TEST(LtsGrid, SidesRunNearestFirstAndEndAtAGapOrAfterTheirReach) {
  const int nx = 12, ny = 5;
  const std::vector<Point3> points = grid(nx, ny, {6 + nx * 2});  // a hole at (3.0, 1.0)
  WindowLists hood, wide;
  std::vector<std::vector<size_t>> lines;
  std::vector<LineSides> sides;
  CHECK_TRUE(grid_neighbourhoods(points, 5, hood, lines, sides, &wide));
  const size_t i = index_at(points, 1.5, 1.0);  // cell (3, 2)
  // Towards +x: cells 4 and 5, then the hole.
  LONGS_EQUAL(2, sides[i][1].size());
  LONGS_EQUAL(index_at(points, 2.0, 1.0), sides[i][1][0]);
  LONGS_EQUAL(index_at(points, 2.5, 1.0), sides[i][1][1]);
  // Towards -x: cells 2, 1, 0, nearest first, then the scan's edge.
  LONGS_EQUAL(3, sides[i][0].size());
  LONGS_EQUAL(index_at(points, 1.0, 1.0), sides[i][0].front());
  LONGS_EQUAL(index_at(points, 0.0, 1.0), sides[i][0][2]);
  // From the first cell of the top row towards +x: eleven cells, of which the side holds its reach.
  const size_t corner = index_at(points, 0.0, 2.0);
  LONGS_EQUAL(kLineReach, sides[corner][1].size());
  size_t expected_x = 1;
  for (size_t j : sides[corner][1]) DOUBLES_EQUAL(0.5 * static_cast<double>(expected_x++), points[j].x, 1e-12);
  CHECK_TRUE(sides[corner][0].empty());
  // Windows shift inwards at the edges: the corner's 5 x 5 window spans cells 0 to 4 of the last
  // five rows; the 7 x 7 one all five rows and cells 0 to 6, less the hole.
  LONGS_EQUAL(25, hood[corner].size());
  for (size_t j : hood[corner]) CHECK(points[j].x <= 2.0 + 1e-12);
  LONGS_EQUAL(34, wide[corner].size());
  // A window holds its own point: cells 1 to 5 round cell 3, all there. Round cell 5 it spans
  // cells 3 to 7 and lacks the hole.
  LONGS_EQUAL(25, hood[i].size());
  bool holds_itself = false;
  for (size_t j : hood[i]) holds_itself = holds_itself || j == i;
  CHECK_TRUE(holds_itself);
  LONGS_EQUAL(24, hood[index_at(points, 2.5, 1.0)].size());
}

TEST(LtsGrid, ScatteredPointsAreNoGrid) {
  const std::vector<Point3> points = {{0, 0, 0}, {1.3, 0.2, 0}, {0.4, 2.9, 0}, {3.7, 1.1, 0}, {2.2, 2.05, 0}};
  WindowLists hood;
  std::vector<std::vector<size_t>> lines;
  std::vector<LineSides> sides;
  CHECK_FALSE(grid_neighbourhoods(points, 5, hood, lines, sides));
}

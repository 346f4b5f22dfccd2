// The trim raster: never "inside" where the exact classifier says outside, and most of a face's
// inside answered without asking it.
#include "host/cad/trim_grid.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;

// A 10 x 10 square with a hole of radius 2 at (5, 5), as its exact classifier and its polygons.
bool in_plate(double u, double v) { return u > 0 && u < 10 && v > 0 && v < 10 && std::hypot(u - 5, v - 5) > 2; }

std::vector<dg::host::TrimGrid::Segment> plate_polygons(int hole_pieces) {
  std::vector<dg::host::TrimGrid::Segment> s = {{0, 0, 10, 0}, {10, 0, 10, 10}, {10, 10, 0, 10}, {0, 10, 0, 0}};
  for (int k = 0; k < hole_pieces; ++k) {
    const double a0 = 2 * kPi * k / hole_pieces, a1 = 2 * kPi * (k + 1) / hole_pieces;
    s.push_back({5 + 2 * std::cos(a0), 5 + 2 * std::sin(a0), 5 + 2 * std::cos(a1), 5 + 2 * std::sin(a1)});
  }
  return s;
}

}  // namespace

TEST_GROUP(TrimGrid){};

TEST(TrimGrid, SaysInsideOnlyWhereTheFaceIsAndAnswersMostOfItAlone) {
  const int pieces = 16;
  const double sagitta = 2 * (1 - std::cos(kPi / pieces));  // of a chord of the hole
  const dg::host::TrimGrid grid(plate_polygons(pieces), sagitta, in_plate, 32);
  size_t inside = 0, answered = 0;
  for (int j = 0; j <= 400; ++j) {
    for (int i = 0; i <= 400; ++i) {
      const double u = -0.5 + 11.0 * i / 400, v = -0.5 + 11.0 * j / 400;
      const bool sure = grid.surely_inside(u, v);
      if (sure) CHECK_TRUE(in_plate(u, v));
      inside += in_plate(u, v);
      answered += sure;
    }
  }
  CHECK_TRUE(answered > inside / 2);
}

// The chords of a coarse hole cut into it; the stated sagitta keeps the raster from calling the
// slivers between chord and circle inside, so the classifier decides there.
TEST(TrimGrid, KeepsAwayFromTheTrueCurveNotJustItsChords) {
  const int pieces = 6;
  const double sagitta = 2 * (1 - std::cos(kPi / pieces));
  const dg::host::TrimGrid grid(plate_polygons(pieces), sagitta, in_plate, 64);
  for (int k = 0; k < 720; ++k) {
    const double a = 2 * kPi * k / 720;
    for (double r : {1.75, 1.9, 1.99}) CHECK_FALSE(grid.surely_inside(5 + r * std::cos(a), 5 + r * std::sin(a)));
  }
}

TEST(TrimGrid, AnEmptyOrDegenerateBoundaryAnswersNothing) {
  CHECK_FALSE(dg::host::TrimGrid().surely_inside(1, 1));
  CHECK_FALSE(dg::host::TrimGrid({}, 0, in_plate).surely_inside(1, 1));
  CHECK_FALSE(dg::host::TrimGrid({{1, 1, 1, 1}}, 0, in_plate).surely_inside(1, 1));
  CHECK_FALSE(dg::host::TrimGrid(plate_polygons(8), NAN, in_plate).surely_inside(1, 1));
}

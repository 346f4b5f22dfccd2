// Height maps for bCNC, Candle and Klipper: each round-trips, each reads a file laid out as its
// program writes one (the programs' own save functions are the oracle for the layout), and a
// scan that is not a full even grid is refused with the node that is wrong.
#include "host/scan/height_map.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "hw/sim/parts.h"

using namespace dg::host;

namespace {

// The saddle's true heights on a 9 x 6 grid from (10, 20), 2.5 x 1.5 mm apart.
std::vector<Point3> saddle_grid() {
  std::vector<Point3> points;
  for (int j = 0; j < 6; ++j) {
    for (int i = 0; i < 9; ++i) {
      const double x = 10 + 2.5 * i, y = 20 + 1.5 * j;
      points.push_back({x, y, dg::sim::shape_height_mm(dg::sim::PartKind::kSaddle, x, y)});
    }
  }
  return points;
}

void check_same(const HeightMap& a, const HeightMap& b) {
  LONGS_EQUAL(a.count_x, b.count_x);
  LONGS_EQUAL(a.count_y, b.count_y);
  DOUBLES_EQUAL(a.min_x_mm, b.min_x_mm, 1e-6);
  DOUBLES_EQUAL(a.max_x_mm, b.max_x_mm, 1e-6);
  DOUBLES_EQUAL(a.min_y_mm, b.min_y_mm, 1e-6);
  DOUBLES_EQUAL(a.max_y_mm, b.max_y_mm, 1e-6);
  for (size_t k = 0; k < a.z_mm.size(); ++k) DOUBLES_EQUAL(a.z_mm[k], b.z_mm[k], 1e-6);
}

std::string refusal(const std::vector<Point3>& points) {
  try {
    height_map_from_points(points, "part.scan");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_GROUP(HeightMap){};

TEST(HeightMap, AGridScanBecomesAMapWithRowsFromMinY) {
  const HeightMap m = height_map_from_points(saddle_grid(), "part.scan");
  LONGS_EQUAL(9, m.count_x);
  LONGS_EQUAL(6, m.count_y);
  DOUBLES_EQUAL(30, m.max_x_mm, 1e-12);
  DOUBLES_EQUAL(27.5, m.max_y_mm, 1e-12);
  DOUBLES_EQUAL(dg::sim::shape_height_mm(dg::sim::PartKind::kSaddle, 12.5, 21.5), m.z(1, 1), 1e-12);
}

TEST(HeightMap, EachFormatRoundTrips) {
  const HeightMap m = height_map_from_points(saddle_grid(), "part.scan");
  check_same(m, parse_bcnc_probe(format_bcnc_probe(m), "part.probe"));
  check_same(m, parse_candle_map(format_candle_map(m), "part.map"));
  check_same(m, parse_klipper_mesh(format_klipper_mesh(m, "saddle"), "printer.cfg"));
}

TEST(HeightMap, ReadsABcncFileAsBcncWritesIt) {
  // Probe.save: "%g" numbers, two blank lines after the header, a blank line after each row.
  const std::string text = "0 10 3\n0 20 2\n-10 3 10\n\n\n0 0 0.1\n5 0 0.2\n10 0 0.3\n\n0 20 1.1\n5 20 1.2\n10 20 1.3\n\n";
  const HeightMap m = parse_bcnc_probe(text, "a.probe");
  DOUBLES_EQUAL(0.2, m.z(1, 0), 1e-12);
  DOUBLES_EQUAL(1.3, m.z(2, 1), 1e-12);
}

TEST(HeightMap, ReadsACandleFileAsCandleWritesIt) {
  // saveHeightMap: border x;y;width;height, grid points and z range, interpolation, then rows.
  const std::string text = "5;7;10;20\r\n3;2;-1;1\r\n0;30;30\r\n0.1;0.2;0.3\r\n1.1;1.2;1.3\r\n";
  const HeightMap m = parse_candle_map(text, "a.map");
  DOUBLES_EQUAL(15, m.max_x_mm, 1e-12);
  DOUBLES_EQUAL(27, m.max_y_mm, 1e-12);
  DOUBLES_EQUAL(0.3, m.z(2, 0), 1e-12);
  DOUBLES_EQUAL(1.1, m.z(0, 1), 1e-12);
}

TEST(HeightMap, ReadsAKlipperProfileAmongTheRestOfPrinterCfg) {
  const std::string text =
      "[printer]\nkinematics: cartesian\n\n#*# <---------------------- SAVE_CONFIG ---------------------->\n"
      "#*# DO NOT EDIT THIS BLOCK OR BELOW. The contents are auto-generated.\n#*#\n#*# [probe]\n#*# z_offset = 1.2\n#*#\n"
      "#*# [bed_mesh default]\n#*# version = 1\n#*# points =\n#*# \t  0.010000, 0.020000, 0.030000\n"
      "#*# \t  0.110000, 0.120000, 0.130000\n#*# \t  0.210000, 0.220000, 0.230000\n#*# x_count = 3\n#*# y_count = 3\n"
      "#*# mesh_x_pps = 2\n#*# mesh_y_pps = 2\n#*# algo = lagrange\n#*# tension = 0.2\n#*# min_x = 20.0\n#*# max_x = 180.0\n"
      "#*# min_y = 20.0\n#*# max_y = 180.0\n#*#\n#*# [extruder]\n#*# pid_kp = 20\n";
  const HeightMap m = parse_klipper_mesh(text, "printer.cfg");
  LONGS_EQUAL(3, m.count_y);
  DOUBLES_EQUAL(180, m.max_x_mm, 1e-12);
  DOUBLES_EQUAL(0.12, m.z(1, 1), 1e-12);
  DOUBLES_EQUAL(0.21, m.z(0, 2), 1e-12);
}

TEST(HeightMap, AScanThatStoppedEarlyOrIsScatteredIsRefused) {
  std::vector<Point3> points = saddle_grid();
  points.pop_back();
  STRCMP_CONTAINS("53 points are not a full 9 x 6 grid", refusal(points).c_str());
  points = saddle_grid();
  points[10].x += 0.4;  // off its node but not on another line
  points[19].x += 0.4;
  points[28].x += 0.4;
  points[37].x += 0.4;
  points[46].x += 0.4;
  points[1].x += 0.4;
  STRCMP_CONTAINS("off an evenly spaced grid", refusal(points).c_str());
  points = saddle_grid();
  points[1] = points[0];
  points[1].z += 1;
  STRCMP_CONTAINS("two points at the node x 10.000000, y 20.000000", refusal(points).c_str());
}

TEST(HeightMap, KlipperNeedsThreePointsASide) {
  HeightMap m;
  m.count_x = 4, m.count_y = 2, m.max_x_mm = 3, m.max_y_mm = 1;
  m.z_mm.assign(8, 0.0);
  CHECK_THROWS(std::invalid_argument, format_klipper_mesh(m, "p"));
}

TEST(HeightMap, ABadNumberOrAShortRowNamesItsLine) {
  try {
    parse_candle_map("0;0;10;10\r\n2;2;-1;1\r\n0;2;2\r\n0.1;0.2\r\n0.3;x\r\n", "a.map");
    FAIL("a map with 'x' for a height was read");
  } catch (const PointFileError& e) {
    STRCMP_CONTAINS("a.map:5: 'x' is not a number", e.what());
  }
  try {
    parse_bcnc_probe("0 10 3\n0 20 2\n-10 3 10\n0 0 0.1\n", "a.probe");
    FAIL("a probe file with 1 point for 6 nodes was read");
  } catch (const PointFileError& e) {
    STRCMP_CONTAINS("1 points for a 3 x 2 grid", e.what());
  }
  try {
    parse_klipper_mesh("#*# [bed_mesh p]\n#*# version = 1\n#*# points =\n#*# \t  1, 2, nan\n#*# \t  1, 2, 3\n#*# \t  1, 2, 3\n"
                       "#*# x_count = 3\n#*# y_count = 3\n#*# min_x = 0\n#*# max_x = 2\n#*# min_y = 0\n#*# max_y = 2\n",
                       "p.cfg");
    FAIL("a Klipper profile with nan was read");
  } catch (const PointFileError& e) {
    STRCMP_CONTAINS("p.cfg:4: 'nan' is not a finite number", e.what());
  }
}

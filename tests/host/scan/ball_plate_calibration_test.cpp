// The axes' scale and squareness from a ball plate, against the errors put into a simulated scan.
#include <CppUTest/TestHarness.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "host/scan/ball_plate_calibration.h"
#include "host/scan/table_calibration.h"
#include "hw/sim/machine_errors.h"
#include "hw/sim/parts.h"
#include "tests/support/ball_plate.h"

using namespace dg::host;

namespace {

std::vector<Point2> certificate() { return dg::test::ball_plate_certificate(); }

// The plate read at commanded positions on a 1 mm grid by a table with the errors `e`, the plate
// laid `angle_deg` off the table's x axis and moved by (dx, dy) mm: at each commanded point the
// table really is at M m, which is (R (M m) + t) in the plate's frame.
PointCloud plate_scan(const dg::sim::MachineErrors& e, double angle_deg, double dx, double dy, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, 1e-3);
  const double a = angle_deg * 3.14159265358979323846 / 180, c = std::cos(a), s = std::sin(a);
  PointCloud cloud;
  for (int j = 6; j <= 94; ++j)
    for (int i = 6; i <= 94; ++i) {
      double x = 0, y = 0;
      dg::sim::actual_table_xy(e, i, j, &x, &y);
      const double px = c * x - s * y + dx, py = s * x + c * y + dy;
      const double z = dg::sim::shape_height_mm(dg::sim::PartKind::kBallPlate, px, py) + noise(rng);
      cloud.points.push_back({1.0 * i, 1.0 * j, std::round(z * 1e3) * 1e-3});
    }
  return cloud;
}

// A calibration over 0..100 mm whose travel is flat, with axes (all zero) for a test to set.
TableCalibration flat_table_with_axes() {
  TableCalibration c;
  c.x0_mm = 0, c.y0_mm = 0, c.step_x_mm = 100, c.step_y_mm = 100, c.nx = 2, c.ny = 2;
  c.z_error_mm.assign(4, 0.0);
  c.u_mm.assign(4, 0.0);
  c.has_axes = true;
  return c;
}

}  // namespace

TEST_GROUP(BallPlateCalibration){};

TEST(BallPlateCalibration, RecoversScaleAndSquarenessFromAPlateLaidAtAnAngleAndOffset) {
  dg::sim::MachineErrors e;
  e.squareness_urad = 500, e.scale_x_ppm = 200, e.scale_y_ppm = -150;
  const AxisCalibration axes = calibrate_from_ball_plate(plate_scan(e, 1.5, 0.7, -0.4, 3), certificate(), "plate.scan");
  std::printf("\n  scale x %+.1f (u %.1f) ppm, scale y %+.1f (u %.1f) ppm, squareness %+.1f (u %.1f) urad, plate %.3f deg",
              axes.scale_x_ppm, axes.u_scale_x_ppm, axes.scale_y_ppm, axes.u_scale_y_ppm, axes.squareness_urad,
              axes.u_squareness_urad, axes.placement_deg);
  LONGS_EQUAL(9, axes.centres.size());
  DOUBLES_EQUAL(1.5, axes.placement_deg, 0.01);
  CHECK(axes.u_scale_x_ppm > 0 && axes.u_scale_x_ppm < 10);
  // Within 4 u: over 16 simulated plates (two angles, eight seeds) the centres' fits leave a bias
  // of up to 6 ppm (0.2 um over 35 mm) that the centres' scatter does not show; 3.2 u at worst.
  DOUBLES_EQUAL(200, axes.scale_x_ppm, 4 * axes.u_scale_x_ppm);
  DOUBLES_EQUAL(-150, axes.scale_y_ppm, 4 * axes.u_scale_y_ppm);
  DOUBLES_EQUAL(500, axes.squareness_urad, 4 * axes.u_squareness_urad);
}

TEST(BallPlateCalibration, AnIdealTableGivesNoErrorWithinItsUncertainty) {
  const AxisCalibration axes = calibrate_from_ball_plate(plate_scan(dg::sim::MachineErrors{}, 0, 0, 0, 4), certificate(), "plate.scan");
  DOUBLES_EQUAL(0, axes.scale_x_ppm, 3 * axes.u_scale_x_ppm);
  DOUBLES_EQUAL(0, axes.scale_y_ppm, 3 * axes.u_scale_y_ppm);
  DOUBLES_EQUAL(0, axes.squareness_urad, 3 * axes.u_squareness_urad);
  CHECK(axes.straightness.measured);
  DOUBLES_EQUAL(0, axes.straightness.x_um, 3 * axes.straightness.u_x_um);
  DOUBLES_EQUAL(0, axes.straightness.y_um, 3 * axes.straightness.u_y_um);
}

// The simulated ways bow by S at mid-travel (4 S v (1 - v) over 100 mm): over the plate's 70 mm
// between its outer balls, centred on the travel, the sagitta is S (35 / 50)^2 (a half span h: S (h / 50)^2).
TEST(BallPlateCalibration, RecoversBentWaysBesideScaleAndSquarenessOnATurnedPlate) {
  dg::sim::MachineErrors e;
  e.squareness_urad = 500, e.scale_x_ppm = 200, e.scale_y_ppm = -150;
  e.straightness_x_um = 8, e.straightness_y_um = -5;
  const AxisCalibration axes = calibrate_from_ball_plate(plate_scan(e, 1.5, 0.7, -0.4, 6), certificate(), "plate.scan");
  const Straightness& bow = axes.straightness;
  std::printf("\n  straightness %+.2f (u %.2f) and %+.2f (u %.2f) um over %.1f and %.1f mm; squareness %+.1f (u %.1f) urad",
              bow.x_um, bow.u_x_um, bow.y_um, bow.u_y_um, 2 * bow.half_span_y_mm, 2 * bow.half_span_x_mm, axes.squareness_urad,
              axes.u_squareness_urad);
  CHECK(bow.measured);
  // The turned plate's outer balls span a little more than 70 mm of commanded travel.
  DOUBLES_EQUAL(35.9, bow.half_span_y_mm, 0.2);
  CHECK(bow.u_x_um > 0 && bow.u_x_um < 1);
  const double over_span_y = std::pow(bow.half_span_y_mm / 50, 2), over_span_x = std::pow(bow.half_span_x_mm / 50, 2);
  DOUBLES_EQUAL(8 * over_span_y, bow.x_um, 4 * bow.u_x_um);
  DOUBLES_EQUAL(-5 * over_span_x, bow.y_um, 4 * bow.u_y_um);
  // The bow is centred on the plate, so it leaves the squareness and scales where they were.
  DOUBLES_EQUAL(500, axes.squareness_urad, 4 * axes.u_squareness_urad);
  DOUBLES_EQUAL(200, axes.scale_x_ppm, 4 * axes.u_scale_x_ppm);
  // Corrected by the whole model, each ball's centre lands on the table's true position.
  TableCalibration c = flat_table_with_axes();
  c.scale_x_ppm = axes.scale_x_ppm, c.scale_y_ppm = axes.scale_y_ppm, c.squareness_urad = axes.squareness_urad;
  c.straightness = bow;
  PointCloud grid;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j) grid.points.push_back({15 + 17.5 * i, 15 + 17.5 * j, 0});
  const PointCloud commanded = grid;
  apply_calibration(c, grid, "grid");
  // The placement's offset is the plate's, not the table's: compared up to one shift for all.
  double worst = 0, shift_x = 0, shift_y = 0;
  for (size_t k = 0; k < grid.points.size(); ++k) {
    double x = 0, y = 0;
    dg::sim::actual_table_xy(e, commanded.points[k].x, commanded.points[k].y, &x, &y);
    if (k == 0) shift_x = grid.points[0].x - x, shift_y = grid.points[0].y - y;
    worst = std::fmax(worst, std::hypot(grid.points[k].x - x - shift_x, grid.points[k].y - y - shift_y));
  }
  std::printf(", corrected grid within %.2f um", worst * 1e3);
  CHECK(worst < 0.0015);
}

// A plate of two rows cannot tell a bow from a leaning way: the bows are not measured, not guessed.
TEST(BallPlateCalibration, APlateOfTwoRowsLeavesTheStraightnessUnmeasured) {
  std::vector<Point2> two_rows;
  for (const Point2& ball : certificate()) {
    if (ball.y < 60) two_rows.push_back(ball);
  }
  const AxisCalibration axes = calibrate_from_ball_plate(plate_scan(dg::sim::MachineErrors{}, 0, 0, 0, 7), two_rows, "plate.scan");
  CHECK_FALSE(axes.straightness.measured);
  DOUBLES_EQUAL(0, axes.straightness.dx_mm(90), 0);
  DOUBLES_EQUAL(0, axes.straightness.u_dx_mm(90), 0);
}

TEST(BallPlateCalibration, ABallTheScanMissesIsNamed) {
  std::vector<Point2> certified = certificate();
  certified.push_back({150, 150});
  try {
    calibrate_from_ball_plate(plate_scan(dg::sim::MachineErrors{}, 0, 0, 0, 5), certified, "plate.scan");
    FAIL("a ball outside the scan was accepted");
  } catch (const CalibrationError& error) {
    STRCMP_CONTAINS("ball 10 (expected at 150.000, 150.000 mm) has no readings within 8 mm", error.what());
  }
}

TEST(BallPlateCalibration, TheCertificateIsReadWithItsHeaderAndRefusedWithItsLine) {
  const std::string path = std::string(P_tmpdir) + "/dg_plate_" + std::to_string(getpid()) + ".csv";
  auto write = [&](const char* text) {
    FILE* f = std::fopen(path.c_str(), "w");
    std::fputs(text, f);
    std::fclose(f);
  };
  write("x_mm,y_mm\n15,15\n50,15\n85,15\n15,50\n");
  LONGS_EQUAL(4, read_ball_certificate(path).size());
  write("x_mm,y_mm\n15,15\n50;15\n85,15\n15,50\n");
  try {
    read_ball_certificate(path);
    FAIL("a bad line was accepted");
  } catch (const CalibrationError& error) {
    STRCMP_CONTAINS(":3: expected x_mm,y_mm, got '50;15'", error.what());
  }
  write("15,15\n50,15\n");
  CHECK_THROWS(CalibrationError, read_ball_certificate(path));
  std::remove(path.c_str());
}

// With the axes in the calibration, each corrected point moves to where the table really was.
TEST(BallPlateCalibration, ACalibrationWithAxesMovesEachPointToWhereTheTableWas) {
  TableCalibration c = flat_table_with_axes();
  c.scale_x_ppm = 200, c.scale_y_ppm = -150, c.squareness_urad = 500;
  c.straightness.measured = true;
  c.straightness.x_um = 3.92, c.straightness.y_um = -2.45, c.straightness.u_x_um = 0.1, c.straightness.u_y_um = 0.1;
  c.straightness.centre_x_mm = 50, c.straightness.centre_y_mm = 50;
  c.straightness.half_span_x_mm = 35, c.straightness.half_span_y_mm = 35;
  const std::string json = calibration_to_json(c);
  STRCMP_CONTAINS("\"version\": 3", json.c_str());
  const TableCalibration back = calibration_from_json(json, "t.json");
  CHECK(back.has_axes);
  CHECK(back.straightness.measured);
  PointCloud cloud;
  cloud.points = {{100, 100, 1}};
  apply_calibration(back, cloud, "part.scan");
  dg::sim::MachineErrors e;
  e.squareness_urad = 500, e.scale_x_ppm = 200, e.scale_y_ppm = -150;
  e.straightness_x_um = 8, e.straightness_y_um = -5;  // 3.92 and -2.45 over the middle 70 mm
  double x = 0, y = 0;
  dg::sim::actual_table_xy(e, 100, 100, &x, &y);
  // The same parabola as the simulator's, and like it nothing at the commanded origin.
  DOUBLES_EQUAL(x, cloud.points[0].x, 1e-9);
  DOUBLES_EQUAL(y, cloud.points[0].y, 1e-9);
  cloud.points = {{0, 50, 1}, {50, 0, 1}};
  apply_calibration(back, cloud, "part.scan");
  dg::sim::actual_table_xy(e, 0, 50, &x, &y);
  DOUBLES_EQUAL(x, cloud.points[0].x, 1e-9);  // 8 um of bow at mid-travel of y, beside the lean
  DOUBLES_EQUAL(50 * std::sin(500e-6) + 0.008, cloud.points[0].x, 1e-9);
  dg::sim::actual_table_xy(e, 50, 0, &x, &y);
  DOUBLES_EQUAL(y, cloud.points[1].y, 1e-9);
}

// A file that says it is version 2 but carries a bow was edited: refused, not half applied.
TEST(BallPlateCalibration, AStraightnessInAVersion2FileIsRefused) {
  TableCalibration c = flat_table_with_axes();
  c.straightness.measured = true;
  c.straightness.half_span_x_mm = c.straightness.half_span_y_mm = 35;
  std::string json = calibration_to_json(c);
  const size_t at = json.find("\"version\": 3");
  CHECK(at != std::string::npos);
  json.replace(at, 12, "\"version\": 2");
  CHECK_THROWS(CalibrationError, calibration_from_json(json, "t.json"));
  c.straightness.measured = false;
  STRCMP_CONTAINS("\"version\": 1", calibration_to_json(c).c_str());
}

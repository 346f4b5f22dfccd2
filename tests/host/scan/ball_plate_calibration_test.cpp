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
  TableCalibration c;
  c.x0_mm = 0, c.y0_mm = 0, c.step_x_mm = 100, c.step_y_mm = 100, c.nx = 2, c.ny = 2;
  c.z_error_mm.assign(4, 0.0);
  c.u_mm.assign(4, 0.0);
  c.has_axes = true;
  c.scale_x_ppm = 200, c.scale_y_ppm = -150, c.squareness_urad = 500;
  const TableCalibration back = calibration_from_json(calibration_to_json(c), "t.json");
  CHECK(back.has_axes);
  PointCloud cloud;
  cloud.points = {{100, 100, 1}};
  apply_calibration(back, cloud, "part.scan");
  dg::sim::MachineErrors e;
  e.squareness_urad = 500, e.scale_x_ppm = 200, e.scale_y_ppm = -150;
  double x = 0, y = 0;
  dg::sim::actual_table_xy(e, 100, 100, &x, &y);
  DOUBLES_EQUAL(x, cloud.points[0].x, 1e-12);
  DOUBLES_EQUAL(y, cloud.points[0].y, 1e-12);
}

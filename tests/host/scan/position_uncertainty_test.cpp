// The table's position uncertainty in each point's height: slopes from a scan's neighbours in any
// line direction, the motor step's share, and a ball-plate calibration's scale and squareness.
#include "host/scan/position_uncertainty.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <random>

using namespace dg::host;

namespace {

// A serpentine scan of z(x, y) in mm, lines along x (or along y), every `step_mm`.
template <typename Height>
ScanData scan_of(Height z, int nx, int ny, double step_mm, bool lines_along_x, uint32_t axis_step_nm) {
  ScanData scan;
  scan.device = digitizer_Hello{};
  scan.device->axis_resolution_nm = axis_step_nm;
  const int lines = lines_along_x ? ny : nx, per_line = lines_along_x ? nx : ny;
  uint32_t seq = 0;
  for (int l = 0; l < lines; ++l) {
    for (int k = 0; k < per_line; ++k) {
      const int along = l % 2 == 0 ? k : per_line - 1 - k;
      const double x = (lines_along_x ? along : l) * step_mm, y = (lines_along_x ? l : along) * step_mm;
      dg::PointSample p;
      p.seq = ++seq;
      p.line = static_cast<uint32_t>(l);
      p.x_nm = static_cast<int32_t>(std::lround(x * 1e6));
      p.y_nm = static_cast<int32_t>(std::lround(y * 1e6));
      p.z_nm = static_cast<int32_t>(std::lround(z(x, y) * 1e6));
      scan.points.push_back(p);
    }
  }
  return scan;
}

double plane(double x, double y) { return 2.0 + 0.1 * x - 0.05 * y; }

}  // namespace

TEST_GROUP(PositionUncertainty){};

TEST(PositionUncertainty, FindsAPlanesSlopeAtEveryPointWhicheverWayTheLinesRun) {
  for (bool along_x : {true, false}) {
    const ScanData scan = scan_of(plane, 21, 16, 0.5, along_x, 2500);
    const auto slopes = scan_slopes(scan);
    LONGS_EQUAL(scan.points.size(), slopes.size());
    for (const auto& [gx, gy] : slopes) {  // corners and edges too: one-sided neighbours suffice
      DOUBLES_EQUAL(0.1, gx, 1e-6);
      DOUBLES_EQUAL(-0.05, gy, 1e-6);
    }
  }
}

TEST(PositionUncertainty, AddsTheStepTimesTheSlopeAndNothingOnAFlat) {
  // A 2.5 um motor step: u = 2.5 / sqrt(12) um along each axis.
  const double u_step_mm = 2.5e-3 / std::sqrt(12.0);
  ScanData sloped = scan_of(plane, 11, 9, 1.0, true, 2500);
  std::vector<double> sigma(sloped.points.size(), 0.002);
  const double added = add_position_uncertainty(sloped, table_position(sloped, std::nullopt), sigma);
  const double expected = u_step_mm * std::hypot(0.1, 0.05);
  DOUBLES_EQUAL(expected, added, 1e-9);
  for (double s : sigma) DOUBLES_EQUAL(std::hypot(0.002, expected), s, 1e-9);

  ScanData flat = scan_of([](double, double) { return 1.5; }, 11, 9, 1.0, true, 2500);
  std::vector<double> flat_sigma(flat.points.size(), 0.002);
  DOUBLES_EQUAL(0.0, add_position_uncertainty(flat, table_position(flat, std::nullopt), flat_sigma), 0);
  for (double s : flat_sigma) DOUBLES_EQUAL(0.002, s, 0);
}

TEST(PositionUncertainty, ACalibratedScaleWeighsMoreFarFromTheOrigin) {
  // 50 ppm uncertain x scale on a 0.2-steep ramp in x: 100 mm out, 5 um of x, 1 um of z.
  TableCalibration c;
  c.has_axes = true;
  c.u_scale_x_ppm = 50;
  ScanData ramp = scan_of([](double x, double) { return 0.2 * x; }, 11, 3, 10.0, true, 0);
  std::vector<double> sigma(ramp.points.size(), 0.0);
  const TablePosition table = table_position(ramp, c);
  DOUBLES_EQUAL(0.0, table.step_mm, 0);
  const double added = add_position_uncertainty(ramp, table, sigma);
  DOUBLES_EQUAL(0.2 * 100.0 * 50e-6, added, 1e-9);
  for (size_t i = 0; i < sigma.size(); ++i) {
    DOUBLES_EQUAL(0.2 * (ramp.points[i].x_nm * 1e-6) * 50e-6, sigma[i], 1e-9);
  }
}

TEST(PositionUncertainty, AgreesWithTheSpreadOfHeightsReadWhereTheTableReallyStood) {
  // Monte Carlo against the first-order formula on a curved part: shift the table by a uniform
  // error of one step and look at the heights' spread at each point.
  auto bump = [](double x, double y) { return 1.0 + 0.02 * x * x - 0.01 * x * y + 0.03 * y * y; };
  const ScanData scan = scan_of(bump, 9, 7, 1.0, true, 10000);  // a coarse 10 um step
  std::vector<double> sigma(scan.points.size(), 0.0);
  add_position_uncertainty(scan, table_position(scan, std::nullopt), sigma);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> half_step(-0.005, 0.005);
  for (size_t i = 0; i < scan.points.size(); i += 7) {
    const double x = scan.points[i].x_nm * 1e-6, y = scan.points[i].y_nm * 1e-6;
    double sum = 0, sum_sq = 0;
    constexpr int kDraws = 20000;
    for (int d = 0; d < kDraws; ++d) {
      const double z = bump(x + half_step(rng), y + half_step(rng));
      sum += z, sum_sq += z * z;
    }
    const double mean = sum / kDraws, spread = std::sqrt(sum_sq / kDraws - mean * mean);
    if (spread < 1e-5) continue;  // at the bottom the first order has nothing to say
    // The scan's slopes come from differences 1 mm apart, exact for a quadratic inside the scan
    // and one-sided at its edges.
    DOUBLES_EQUAL(spread, sigma[i], 0.15 * spread);
  }
}

// A bow measured over 70 mm about y = 50 is uncertain by u at the span's ends and by nothing at
// the commanded origin (where every correction is zero); beyond the plate it grows with the square.
TEST(PositionUncertainty, AMeasuredBowAddsItsUncertaintyByTheSquareOfTheDistance) {
  TableCalibration c;
  c.has_axes = true;
  c.straightness.measured = true;
  c.straightness.u_x_um = 0.5, c.straightness.u_y_um = 0.2;
  c.straightness.centre_x_mm = c.straightness.centre_y_mm = 50;
  c.straightness.half_span_x_mm = c.straightness.half_span_y_mm = 35;
  ScanData scan;
  const TablePosition t = table_position(scan, c);
  DOUBLES_EQUAL(0, t.u_x_mm(0, 0, 0), 1e-15);
  // At y = 85: ((35)^2 - 50^2) / 35^2 of the sagitta's u.
  DOUBLES_EQUAL(0.5e-3 * (2500 - 1225) / 1225, t.u_x_mm(0, 85, 0), 1e-12);
  DOUBLES_EQUAL(0.2e-3 * (2500 - 1225) / 1225, t.u_y_mm(15, 0, 0), 1e-12);
  CHECK(t.u_x_mm(0, 150, 0) > 5 * t.u_x_mm(0, 85, 0));
}

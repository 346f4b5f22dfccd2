// The travel's height-error map from a flat, against the simulated machine's true map.
#include <CppUTest/TestHarness.h>

#include <cmath>
#include <random>

#include "host/scan/flat_calibration.h"
#include "hw/sim/machine_errors.h"

using namespace dg::host;

namespace {

// A flat at 5 mm, tilted by its setup, on a table whose travel is 30 um out of flat: read on a grid
// with gauge noise and 1 um readings, as the simulator's gauge does.
PointCloud flat_scan(const dg::sim::MachineErrors& e, double step_mm, double noise_um, unsigned seed) {
  const double peak = dg::sim::flatness_map_peak(e.map_seed);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, noise_um * 1e-3);
  PointCloud c;
  for (double y = 0; y <= 100 + 1e-9; y += step_mm)
    for (double x = 0; x <= 100 + 1e-9; x += step_mm) {
      const double z = 5 + 2e-4 * x - 1e-4 * y + dg::sim::travel_z_error_mm(e, peak, x, y) + noise(rng);
      c.points.push_back({x, y, std::round(z * 1e3) * 1e-3});
    }
  c.resolution_mm = 1e-3;
  return c;
}

dg::sim::MachineErrors bent_table() {
  dg::sim::MachineErrors e;
  e.flatness_um = 30;
  return e;
}

}  // namespace

TEST_GROUP(FlatCalibration){};

// The map is known up to a plane (the flat's setup); between the nodes, everywhere on a 1 mm grid,
// the corrected travel is flat within 1.5 um, and the map's U = 2u covers its own error.
TEST(FlatCalibration, TheMapMatchesTheTrueTravelErrorBetweenItsNodesUpToAPlane) {
  const dg::sim::MachineErrors e = bent_table();
  const TableCalibration c = calibrate_from_flat(flat_scan(e, 5, 1, 4), 0, "flat.scan");
  LONGS_EQUAL(21, c.nx);
  LONGS_EQUAL(21, c.ny);
  DOUBLES_EQUAL(1e-3, c.noise_mm, 0.15e-3);
  const double peak = dg::sim::flatness_map_peak(e.map_seed);
  // The true error less the map, on a dense grid; a plane fitted to it is what the flat cannot tell.
  std::vector<Point3> difference;
  for (int i = 0; i <= 100; ++i)
    for (int j = 0; j <= 100; ++j) difference.push_back({1.0 * i, 1.0 * j, dg::sim::travel_z_error_mm(e, peak, i, j) - c.z_error_at(i, j)});
  double sx = 0, sy = 0, sz = 0, sxx = 0, syy = 0, sxz = 0, syz = 0, n = 0;
  for (const Point3& p : difference) sx += p.x, sy += p.y, sz += p.z, sxx += p.x * p.x, syy += p.y * p.y, sxz += p.x * p.z, syz += p.y * p.z, ++n;
  // The grid is symmetric, so x and y decouple: slopes and intercept in closed form.
  const double bx = (sxz - sx * sz / n) / (sxx - sx * sx / n), by = (syz - sy * sz / n) / (syy - sy * sy / n);
  const double a = (sz - bx * sx - by * sy) / n;
  double worst = 0, worst_over_u = 0;
  for (const Point3& p : difference) {
    const double r = std::fabs(p.z - (a + bx * p.x + by * p.y));
    worst = std::fmax(worst, r);
    worst_over_u = std::fmax(worst_over_u, r / c.u_at(p.x, p.y));
  }
  std::printf("\n  map vs the true 30 um travel error (up to a plane): worst %.2f um, %.1f u; u max %.2f um", worst * 1e3,
              worst_over_u, c.u_at(0, 0) * 1e3);
  CHECK(worst < 1.5e-3);
  CHECK(worst_over_u < 4);
}

TEST(FlatCalibration, TheFlatsCertifiedFlatnessAddsToEveryNodesUncertainty) {
  const PointCloud scan = flat_scan(bent_table(), 10, 1, 5);
  const TableCalibration bare = calibrate_from_flat(scan, 0, "flat.scan");
  const TableCalibration certified = calibrate_from_flat(scan, 0.002, "flat.scan");
  const double u_flat = 0.002 / 2 / std::sqrt(3.0);
  DOUBLES_EQUAL(std::hypot(bare.u_mm[60], u_flat), certified.u_mm[60], 1e-12);
}

TEST(FlatCalibration, AScanWithAHoleOrTooFewPointsIsRefusedWithWhereAndWhy) {
  PointCloud scan = flat_scan(bent_table(), 10, 1, 6);
  scan.points.erase(scan.points.begin() + 13);  // (20, 10)
  try {
    calibrate_from_flat(scan, 0, "flat.scan");
    FAIL("a hole was accepted");
  } catch (const CalibrationError& error) {
    STRCMP_CONTAINS("(20.000, 10.000)", error.what());
  }
  PointCloud small = flat_scan(bent_table(), 50, 1, 6);
  try {
    calibrate_from_flat(small, 0, "flat.scan");
    FAIL("a 3 x 3 scan was accepted");
  } catch (const CalibrationError& error) {
    STRCMP_CONTAINS("at least 5", error.what());
  }
  scan = flat_scan(bent_table(), 10, 1, 6);
  scan.points[7].z = std::nan("");
  CHECK_THROWS(CalibrationError, calibrate_from_flat(scan, 0, "flat.scan"));
}

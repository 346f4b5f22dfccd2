// Calibration in the whole system: the simulated table's travel is 30 um out of flat; the table is
// calibrated on a flat, a part scanned later (another scan seed) is corrected by it, a scan outside
// the calibrated travel is refused before the table moves, and a stored scan is re-corrected.
#include <CppUTest/TestHarness.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "host/cli/calibrate_command.h"
#include "host/cli/scan_command.h"
#include "host/scan/point_reader.h"
#include "host/scan/scan_file.h"
#include "host/scan/table_calibration.h"
#include "hw/sim/parts.h"

using namespace dg::host;

namespace {

std::string temp_path(const std::string& name) {
  return std::string(P_tmpdir) + "/dg_calibration_" + std::to_string(getpid()) + "_" + name;
}

constexpr const char* kMachine = "flatness_um=30,noise_um=0.5";

// The calibrated travel, 0..60 x 0..40 mm at 5 mm.
std::string calibrate(const std::string& output) {
  CalibrateArgs a;
  a.device = std::string("sim:part=flat,seed=11,") + kMachine;
  a.x = "0:60", a.y = "0:40";
  a.output = output;
  a.force = true;
  a.quiet = true;
  LONGS_EQUAL(0, run_calibrate(a));
  return output;
}

ScanArgs dome_scan(const std::string& calibration, const std::string& output) {
  ScanArgs s;
  s.device = std::string("sim:part=dome,seed=12,") + kMachine;
  s.calibration = calibration;
  s.output = output;
  s.force = true;
  s.quiet = true;
  return s;
}

}  // namespace

TEST_GROUP(SimCalibration){};

TEST(SimCalibration, ADomeScannedLaterIsCorrectedToItsTrueShapeWithinTwoMicrometresAndTheNoise) {
  const std::string cal = calibrate(temp_path("table.cal.json")), part = temp_path("dome.scan");
  LONGS_EQUAL(0, run_scan(dome_scan(cal, part)));
  const TableCalibration c = read_calibration_file(cal);
  const PointCloud corrected = read_points(part);
  CHECK(!corrected.calibration.empty());
  // What one flat cannot tell: the plane taken out of the map (less the flat's own 5 mm height).
  auto plane = [&](double x, double y) { return c.plane_mm[0] - 5.0 + c.plane_mm[1] * x + c.plane_mm[2] * y; };
  double worst = 0, worst_raw = 0, ss = 0;
  ScanData raw = read_scan_file(part);
  for (size_t k = 0; k < corrected.points.size(); ++k) {
    const Point3& p = corrected.points[k];
    const double truth = dg::sim::shape_height_mm(dg::sim::PartKind::kDome, p.x, p.y);
    const double error = p.z - truth - plane(p.x, p.y);
    worst = std::fmax(worst, std::fabs(error));
    ss += error * error;
    worst_raw = std::fmax(worst_raw, std::fabs(raw.points[k].z_nm * 1e-6 - truth - plane(p.x, p.y)));
  }
  const double rms = std::sqrt(ss / static_cast<double>(corrected.points.size()));
  // 0.5 um of noise read to 1 um: about 0.58 um a reading, up to 3.5 times that over 1,271 points.
  std::printf("\n  dome after calibration: worst %.2f um, RMS %.2f um (uncorrected worst %.1f um)", worst * 1e3, rms * 1e3,
              worst_raw * 1e3);
  CHECK(worst_raw > 0.008);  // the travel over this area is 11 um out of its plane
  CHECK(worst <= 0.002 + 3.5 * 0.00058);
  CHECK(rms <= 0.0009);
  std::remove(part.c_str());
  std::remove(cal.c_str());
  std::remove((cal + ".flat.scan").c_str());
}

TEST(SimCalibration, AScanBeyondTheCalibratedTravelIsRefusedBeforeTheTableMoves) {
  const std::string cal = calibrate(temp_path("small.cal.json")), part = temp_path("wide.scan");
  ScanArgs s = dome_scan(cal, part);
  s.x = "0:70";
  try {
    run_scan(s);
    FAIL("a scan the calibration does not cover was started");
  } catch (const CalibrationError& error) {
    STRCMP_CONTAINS("covers x 0.000..60.000, y 0.000..40.000 mm; the scan asks x 0.000..70.000", error.what());
  }
  CHECK(access(part.c_str(), F_OK) != 0);
  std::remove(cal.c_str());
  std::remove((cal + ".flat.scan").c_str());
}

TEST(SimCalibration, AStoredScanIsRecorrectedByANewerCalibrationAndKeepsItsRawPoints) {
  const std::string cal = calibrate(temp_path("old.cal.json")), part = temp_path("plain.scan");
  LONGS_EQUAL(0, run_scan(dome_scan("none", part)));
  const PointCloud raw = read_points(part);
  CHECK(raw.calibration.empty());
  RecorrectArgs r;
  r.scan = part;
  r.calibration = cal;
  LONGS_EQUAL(0, run_recorrect(r));
  const PointCloud corrected = read_points(part);
  const TableCalibration c = read_calibration_file(cal);
  for (size_t k = 0; k < raw.points.size(); k += 97) {
    DOUBLES_EQUAL(raw.points[k].z - c.z_error_at(raw.points[k].x, raw.points[k].y), corrected.points[k].z, 1e-6);
  }
  LONGS_EQUAL(raw.points.size(), read_scan_file(part).points.size());
  std::remove(part.c_str());
  std::remove(cal.c_str());
  std::remove((cal + ".flat.scan").c_str());
}

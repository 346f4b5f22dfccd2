// Each point's standard uncertainty from a scan's own record: repeatability, reading step, spread flags.
#include "host/scan/scan_uncertainty.h"

#include <CppUTest/TestHarness.h>

#include <cmath>

namespace {

dg::host::ScanData scan_with(uint32_t stddev_nm, uint32_t readings, uint32_t step_nm, uint32_t spread_nm) {
  dg::host::ScanData scan;
  scan.device = digitizer_Hello{};
  scan.device->gauge_resolution_nm = step_nm;
  scan.request = digitizer_ScanRequest{};
  scan.request->spread_tolerance_nm = spread_nm;
  scan.repeatability = digitizer_Repeatability{};
  scan.repeatability->count = readings;
  scan.repeatability->stddev_nm = stddev_nm;
  for (uint32_t i = 0; i < 3; ++i) {
    dg::PointSample p;
    p.seq = i + 1;
    p.x_nm = static_cast<int32_t>(i * 1000000);
    scan.points.push_back(p);
  }
  return scan;
}

}  // namespace

TEST_GROUP(ScanUncertainty){};

TEST(ScanUncertainty, CombinesTheRepeatabilityWithTheReadingStep) {
  const dg::host::ScanPointSigmas s = dg::host::scan_point_sigmas(scan_with(3000, 20, 1000, 0));
  LONGS_EQUAL(3, s.sigma_mm.size());
  // s = 3 um and a 1 um step: sqrt(9 + 1/12) um.
  for (double u : s.sigma_mm) DOUBLES_EQUAL(std::sqrt(9.0 + 1.0 / 12.0) * 1e-3, u, 1e-12);
  STRCMP_CONTAINS("repeatability (s = 0.0030 mm over 20 readings", s.from.c_str());
}

// Readings that never differ (noise far below the step) still leave the rounding: q / sqrt(12).
TEST(ScanUncertainty, AnUnchangingGaugeStillCarriesItsRounding) {
  const dg::host::ScanPointSigmas s = dg::host::scan_point_sigmas(scan_with(0, 10, 10000, 0));
  DOUBLES_EQUAL(0.01 / std::sqrt(12.0), s.sigma_mm[1], 1e-12);
}

TEST(ScanUncertainty, APointWhoseSamplesDisagreedIsWidenedByHalfTheSpreadTolerance) {
  dg::host::ScanData scan = scan_with(2000, 10, 1000, 8000);
  scan.points[1].flags = digitizer_PointFlag_POINT_SPREAD_HIGH;
  const dg::host::ScanPointSigmas s = dg::host::scan_point_sigmas(scan);
  const double base_um2 = 4.0 + 1.0 / 12.0;
  DOUBLES_EQUAL(std::sqrt(base_um2) * 1e-3, s.sigma_mm[0], 1e-12);
  DOUBLES_EQUAL(std::sqrt(base_um2 + 16.0) * 1e-3, s.sigma_mm[1], 1e-12);
  STRCMP_CONTAINS("widened where the samples disagreed", s.from.c_str());
}

TEST(ScanUncertainty, AScanWithoutARepeatabilityRecordStatesNoneAndSaysHowToGetIt) {
  dg::host::ScanData scan = scan_with(2000, 10, 1000, 0);
  scan.repeatability.reset();
  const dg::host::ScanPointSigmas s = dg::host::scan_point_sigmas(scan);
  CHECK(s.sigma_mm.empty());
  STRCMP_CONTAINS("--repeatability", s.from.c_str());
}

TEST(ScanUncertainty, ARecordOfOneReadingIsNotARepeatability) {
  const dg::host::ScanPointSigmas s = dg::host::scan_point_sigmas(scan_with(2000, 1, 1000, 0));
  CHECK(s.sigma_mm.empty());
  STRCMP_CONTAINS("fewer than 2 readings", s.from.c_str());
}

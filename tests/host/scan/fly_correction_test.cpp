// The fly scan's latch delay measured from its serpentine lines and taken out of the positions,
// against scans made here from a known surface and a known delay; lifted readings left out.
#include "host/scan/fly_correction.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

namespace {

double surface_mm(double x_mm, double y_mm) { return 0.6 * std::sin(x_mm / 3.0) + 0.02 * y_mm * x_mm / 10.0; }

struct FlyScanSpec {
  int lines = 6;
  double length_mm = 20;
  double feed_mm_s = 7.5;
  double cycle_ms = 26;
  double delay_ms = 3.0;
  double jitter_ms = 0;
  double nm_per_step = 2500;
};

// Serpentine lines 1 mm apart; each point's position is the step count at its request (the table
// at constant feed), its reading the surface where the table was `delay_ms` later, in whole um.
dg::host::ScanData make_scan(const FlyScanSpec& s, unsigned seed, std::vector<double>* true_x_mm) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> jitter(0.0, s.jitter_ms);
  dg::host::ScanData scan;
  scan.request = digitizer_ScanRequest{};
  scan.request->mode = digitizer_ScanMode_SCAN_MODE_FLY;
  uint64_t t0_us = 1000000;
  uint32_t seq = 1;
  for (int l = 0; l < s.lines; ++l) {
    const double dir = (l % 2) ? -1 : 1;
    const double start = dir > 0 ? 0 : s.length_mm;
    for (double t_ms = 0; t_ms * s.feed_mm_s * 1e-3 <= s.length_mm; t_ms += s.cycle_ms) {
      const double x_mm = start + dir * s.feed_mm_s * t_ms * 1e-3;
      const double latch_ms = s.delay_ms + (s.jitter_ms > 0 ? jitter(rng) : 0.0);
      const double latch_x_mm = x_mm + dir * s.feed_mm_s * latch_ms * 1e-3;
      dg::PointSample p;
      p.seq = seq++;
      p.line = static_cast<uint32_t>(l);
      p.t_us = t0_us + static_cast<uint64_t>(std::llround(t_ms * 1e3));
      p.x_nm = static_cast<int32_t>(std::round(x_mm * 1e6 / s.nm_per_step) * s.nm_per_step);
      p.y_nm = l * 1000000;
      p.z_nm = static_cast<int32_t>(std::llround(surface_mm(latch_x_mm, l) * 1e3) * 1000);
      scan.points.push_back(p);
      if (true_x_mm) true_x_mm->push_back(latch_x_mm);
    }
    t0_us += 4000000;
  }
  return scan;
}

}  // namespace

TEST_GROUP(FlyCorrection){};

TEST(FlyCorrection, MeasuresTheLatchDelayAndMovesEachPointToWhereItWasRead) {
  FlyScanSpec spec;
  std::vector<double> truth;
  dg::host::ScanData scan = make_scan(spec, 1, &truth);
  const auto fix = dg::host::correct_fly_scan(scan, nullptr, "test");
  CHECK(fix.has_value());
  DOUBLES_EQUAL(3.0, fix->latch_delay_ms, 0.1);
  CHECK(fix->u_latch_delay_ms > 0 && fix->u_latch_delay_ms < 0.1);
  CHECK(std::fabs(fix->latch_delay_ms - 3.0) < 3 * fix->u_latch_delay_ms + 0.02);
  DOUBLES_EQUAL(7.5, fix->feed_mm_s, 0.01);
  DOUBLES_EQUAL(7.5 * 0.026, fix->spacing_mm, 0.003);
  LONGS_EQUAL(truth.size(), scan.points.size());
  double worst_um = 0;
  for (size_t i = 0; i < truth.size(); ++i) worst_um = std::fmax(worst_um, std::fabs(scan.points[i].x_nm * 1e-6 - truth[i]) * 1e3);
  // The shift was 22.5 um; left: the delay's error times the feed, and what the line fit leaves
  // of the step count's rounding (2.5 um steps).
  CHECK(worst_um < 0.5);
}

TEST(FlyCorrection, AJitteringLatchLeavesTheMeanDelayAndAnHonestUncertainty) {
  FlyScanSpec spec;
  spec.jitter_ms = 0.3;
  spec.delay_ms = 4.5;
  dg::host::ScanData scan = make_scan(spec, 2, nullptr);
  const auto fix = dg::host::correct_fly_scan(scan, nullptr, "test");
  CHECK(fix.has_value());
  CHECK(std::fabs(fix->latch_delay_ms - 4.5) < 3 * fix->u_latch_delay_ms + 0.02);
  CHECK(fix->u_latch_delay_ms < 0.2);
}

TEST(FlyCorrection, PointSigmaGainsTheShiftsUncertaintyTimesTheSlope) {
  FlyScanSpec spec;
  spec.jitter_ms = 0.3;
  dg::host::ScanData scan = make_scan(spec, 3, nullptr);
  std::vector<double> sigma(scan.points.size(), 0.001);
  const auto fix = dg::host::correct_fly_scan(scan, &sigma, "test");
  LONGS_EQUAL(scan.points.size(), sigma.size());
  double largest = 0;
  for (double s : sigma) {
    CHECK(s >= 0.001);
    largest = std::fmax(largest, s);
  }
  // The steepest slope is 0.2 + 0.02: the largest sigma is sqrt(1 um^2 + (0.22 u_shift)^2) or less.
  CHECK(largest > 0.001);
  CHECK(largest <= std::sqrt(1e-6 + std::pow(0.23 * fix->u_shift_mm, 2)));
}

TEST(FlyCorrection, LiftedReadingsLeaveThePointsAndAreCountedByLine) {
  FlyScanSpec spec;
  dg::host::ScanData scan = make_scan(spec, 4, nullptr);
  const size_t before = scan.points.size();
  scan.points[10].flags |= digitizer_PointFlag_POINT_LIFTED;
  scan.points[11].flags |= digitizer_PointFlag_POINT_LIFTED;
  scan.points[before - 2].flags |= digitizer_PointFlag_POINT_LIFTED;
  std::vector<double> sigma(before, 0.001);
  const auto fix = dg::host::correct_fly_scan(scan, &sigma, "test");
  LONGS_EQUAL(3, fix->lifted);
  LONGS_EQUAL(2, fix->lifted_lines.size());
  LONGS_EQUAL(0, fix->lifted_lines[0]);
  LONGS_EQUAL(spec.lines - 1, fix->lifted_lines[1]);
  LONGS_EQUAL(before - 3, scan.points.size());
  LONGS_EQUAL(before - 3, sigma.size());
  for (const auto& p : scan.points) CHECK((p.flags & digitizer_PointFlag_POINT_LIFTED) == 0);
  STRCMP_CONTAINS("3 readings where the plunger could not follow", dg::host::fly_summary(*fix).c_str());
}

TEST(FlyCorrection, KeepsLiftedReadingsWhenAskedToShowThePointsAsMeasured) {
  FlyScanSpec spec;
  dg::host::ScanData scan = make_scan(spec, 5, nullptr);
  const size_t before = scan.points.size();
  scan.points[10].flags |= digitizer_PointFlag_POINT_LIFTED;
  const auto fix = dg::host::correct_fly_scan(scan, nullptr, "test", false);
  LONGS_EQUAL(1, fix->lifted);
  LONGS_EQUAL(before, scan.points.size());
}

TEST(FlyCorrection, RefusesAScanWhoseDelayCannotBeMeasured) {
  FlyScanSpec spec;
  spec.lines = 1;
  dg::host::ScanData scan = make_scan(spec, 6, nullptr);
  try {
    dg::host::correct_fly_scan(scan, nullptr, "one.scan");
    FAIL("a single line was accepted");
  } catch (const std::invalid_argument& e) {
    STRCMP_CONTAINS("one.scan", e.what());
    STRCMP_CONTAINS("latch delay", e.what());
  }
}

TEST(FlyCorrection, LeavesAStopAndGoScanAlone) {
  FlyScanSpec spec;
  dg::host::ScanData scan = make_scan(spec, 7, nullptr);
  scan.request->mode = digitizer_ScanMode_SCAN_MODE_STOP;
  const int32_t x = scan.points[5].x_nm;
  CHECK_FALSE(dg::host::correct_fly_scan(scan, nullptr, "test").has_value());
  LONGS_EQUAL(x, scan.points[5].x_nm);
}

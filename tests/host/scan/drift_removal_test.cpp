// Drift removal on scans made here with a known drift: the readings come out of the points, the
// drift between them is interpolated in time, and the correction's uncertainty is added.
#include "host/scan/drift_removal.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <functional>
#include <stdexcept>

using namespace dg::host;

namespace {

// One line of `per_line` points 1 mm apart per second of time, a reference reading at (0, 0) after
// every `every` lines; the part is flat at 5 mm and the stand drifts by drift(t) mm.
ScanData drifting_scan(int lines, int per_line, int every, const std::function<double(double)>& drift) {
  ScanData scan;
  uint32_t seq = 0;
  double t_s = 0;
  auto add = [&](int32_t x_nm, int32_t y_nm, uint32_t line, uint32_t flags) {
    dg::PointSample p;
    p.seq = seq++;
    p.line = line;
    p.t_us = static_cast<uint64_t>(std::llround(t_s * 1e6));
    p.x_nm = x_nm, p.y_nm = y_nm;
    p.z_nm = static_cast<int32_t>(std::lround((5.0 + drift(t_s)) * 1e6));
    p.flags = flags;
    scan.points.push_back(p);
    t_s += 1;
  };
  for (int line = 0; line < lines; ++line) {
    for (int k = 0; k < per_line; ++k) {
      uint32_t flags = k == 0 ? digitizer_PointFlag_POINT_LINE_START : 0;
      const bool reference_follows = every > 0 && ((line + 1) % every == 0 || line + 1 == lines);
      if (k + 1 == per_line && !reference_follows) flags |= digitizer_PointFlag_POINT_LINE_END;
      add(k * 1000000, line * 1000000, static_cast<uint32_t>(line), flags);
    }
    if (every > 0 && ((line + 1) % every == 0 || line + 1 == lines)) {
      add(0, 0, static_cast<uint32_t>(line), digitizer_PointFlag_POINT_REFERENCE | digitizer_PointFlag_POINT_LINE_END);
    }
  }
  return scan;
}

double worst_error_mm(const ScanData& scan) {
  double worst = 0;
  for (const dg::PointSample& p : scan.points) worst = std::fmax(worst, std::fabs(p.z_nm * 1e-6 - 5.0));
  return worst;
}

}  // namespace

TEST_GROUP(DriftRemoval){};

TEST(DriftRemoval, AStraightDriftComesOutExactlyAndTheReadingsLeaveThePoints) {
  ScanData scan = drifting_scan(9, 10, 3, [](double t) { return 0.0002 * t; });  // 0.2 um a second
  const size_t with_readings = scan.points.size();
  const std::optional<DriftRemoval> r = remove_drift(scan, nullptr, "test.scan");
  CHECK(r.has_value());
  LONGS_EQUAL(3, r->readings);
  LONGS_EQUAL(with_readings - 3, scan.points.size());
  for (const dg::PointSample& p : scan.points) CHECK((p.flags & digitizer_PointFlag_POINT_REFERENCE) == 0);
  CHECK(worst_error_mm(scan) <= 1e-6);  // rounding to whole nanometres
  DOUBLES_EQUAL(0.0002 * 92, r->largest_mm, 1e-6);  // the last reading, 92 s after the first point
  DOUBLES_EQUAL(0, r->interpolation_mm, 1e-9);      // a straight line has no curvature
}

TEST(DriftRemoval, ACurvedDriftLeavesLessThanTheBoundItStates) {
  auto warm_up = [](double t) { return 0.025 * (1 - std::exp(-t / 60.0)); };  // 25 um, one minute
  ScanData scan = drifting_scan(12, 10, 2, warm_up);
  ScanData untouched = scan;
  const std::optional<DriftRemoval> r = remove_drift(scan, nullptr, "test.scan");
  CHECK(r.has_value());
  remove_drift(untouched, nullptr, "test.scan", false);
  CHECK(worst_error_mm(untouched) > 0.020);
  CHECK(worst_error_mm(scan) <= r->interpolation_mm + 1e-6);
  CHECK(worst_error_mm(scan) < 0.002);
}

TEST(DriftRemoval, EachPointGainsTheReadingsNoiseThroughItsWeightsAndTheFirstPointNone) {
  ScanData scan = drifting_scan(4, 10, 2, [](double t) { return 0.0001 * t; });
  std::vector<double> sigma(scan.points.size(), 0.001);  // 1 um on every reading
  remove_drift(scan, &sigma, "test.scan");
  LONGS_EQUAL(scan.points.size(), sigma.size());
  // The first point is the drift's zero: nothing to add.
  DOUBLES_EQUAL(0.001, sigma[0], 1e-12);
  // Point 10 (t = 10 s) lies between the first point (t = 0) and the reading at t = 20 s: weight
  // 1/2 on that reading, and knot 0 counted once with weight 1/2 - 1: u^2 = 2 (1/2 sigma)^2.
  DOUBLES_EQUAL(std::sqrt(0.001 * 0.001 * (1 + 0.5)), sigma[10], 1e-9);
  // Point 20 (t = 21 s) lies just after the reading at t = 20 s, towards the one at t = 41 s:
  // w = 1/21; u^2 = ((1 - w)^2 + w^2 + 1) sigma^2 on top of its own.
  const double w = 1.0 / 21.0;
  DOUBLES_EQUAL(0.001 * std::sqrt(1 + (1 - w) * (1 - w) + w * w + 1), sigma[20], 1e-9);
}

TEST(DriftRemoval, PointsAfterTheLastReadingAreHeldThereWithTheLastRateAsTheirUncertainty) {
  ScanData scan = drifting_scan(4, 10, 2, [](double t) { return 0.0001 * t; });
  // A scan cut short: the last line's reading never came.
  scan.points.pop_back();
  const double t_last_reading = 20;
  std::vector<double> sigma(scan.points.size(), 0.0);
  const std::optional<DriftRemoval> r = remove_drift(scan, &sigma, "test.scan");
  CHECK(r.has_value());
  LONGS_EQUAL(1, r->readings);
  const dg::PointSample& last = scan.points.back();
  const double t_s = last.t_us * 1e-6;
  // Held at the last reading's drift: off by the drift since, and its uncertainty says as much.
  DOUBLES_EQUAL(0.0001 * (t_s - t_last_reading), last.z_nm * 1e-6 - 5.0, 1e-6);
  DOUBLES_EQUAL(0.0001 * (t_s - t_last_reading) / std::sqrt(3.0), sigma.back(), 1e-6);
}

TEST(DriftRemoval, AScanWithoutReadingsIsLeftAsItIs) {
  ScanData scan = drifting_scan(3, 5, 0, [](double t) { return 0.001 * t; });
  const ScanData before = scan;
  CHECK(!remove_drift(scan, nullptr, "test.scan").has_value());
  LONGS_EQUAL(before.points.size(), scan.points.size());
  for (size_t k = 0; k < scan.points.size(); ++k) LONGS_EQUAL(before.points[k].z_nm, scan.points[k].z_nm);
}

TEST(DriftRemoval, AReadingTakenElsewhereThanTheFirstPointIsRefusedNamingIt) {
  ScanData scan = drifting_scan(4, 5, 2, [](double) { return 0.0; });
  for (dg::PointSample& p : scan.points) {
    if (p.flags & digitizer_PointFlag_POINT_REFERENCE) {
      p.x_nm = 3000000;
      break;
    }
  }
  try {
    remove_drift(scan, nullptr, "odd.scan");
    FAIL("accepted a reading taken elsewhere");
  } catch (const std::invalid_argument& e) {
    STRCMP_CONTAINS("odd.scan: reference reading 10", e.what());
    STRCMP_CONTAINS("not at the scan's first point", e.what());
  }
}

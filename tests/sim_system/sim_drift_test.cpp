// Drift in the whole system: the simulated gauge stand warms up during a scan (a first-order settle
// that no straight line follows, and a steady creep); reading the scan's first point again every
// few lines lets the host take the drift out.
#include <CppUTest/TestHarness.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "host/cli/scan_command.h"
#include "host/scan/drift_removal.h"
#include "host/scan/point_reader.h"
#include "host/scan/scan_file.h"
#include "hw/sim/parts.h"

using namespace dg::host;

namespace {

std::string temp_path(const std::string& name) {
  return std::string(P_tmpdir) + "/dg_drift_" + std::to_string(getpid()) + "_" + name;
}

// 25 um of warm-up with a 3-minute time constant and 20 um an hour of creep, over a 41 x 31 scan of
// about 5 minutes; 0.5 um of gauge noise read to 1 um.
constexpr const char* kDrifting = "sim:part=saddle,seed=5,noise_um=0.5,warmup_um=25,warmup_min=3,drift_um_per_h=20";

ScanArgs saddle_scan(const std::string& output, uint32_t reference_every) {
  ScanArgs s;
  s.device = kDrifting;
  s.x = "0:40", s.y = "0:30";
  s.reference_every = reference_every;
  s.repeatability = 10;
  s.output = output;
  s.force = true;
  s.quiet = true;
  return s;
}

struct Errors {
  double worst_mm = 0, rms_mm = 0;
  size_t points = 0;
};

// The points as every reader gets them, against the saddle's true shape.
Errors against_truth(const PointCloud& cloud) {
  Errors e;
  double ss = 0;
  for (const Point3& p : cloud.points) {
    const double error = p.z - dg::sim::shape_height_mm(dg::sim::PartKind::kSaddle, p.x, p.y);
    e.worst_mm = std::fmax(e.worst_mm, std::fabs(error));
    ss += error * error;
  }
  e.points = cloud.points.size();
  e.rms_mm = std::sqrt(ss / static_cast<double>(e.points));
  return e;
}

}  // namespace

TEST_GROUP(SimDrift){};

TEST(SimDrift, ReadingTheFirstPointAgainEveryTwoLinesTakesAStandsWarmUpOutToTheNoise) {
  const std::string plain = temp_path("plain.scan"), referenced = temp_path("referenced.scan");
  LONGS_EQUAL(0, run_scan(saddle_scan(plain, 0)));
  LONGS_EQUAL(0, run_scan(saddle_scan(referenced, 2)));
  const Errors before = against_truth(read_points(plain));
  const PointCloud cloud = read_points(referenced);
  const Errors after = against_truth(cloud);
  std::printf("\n  drifting stand: worst %.2f um, RMS %.2f um without reference readings; worst %.2f um, RMS %.2f um "
              "with one every two lines",
              before.worst_mm * 1e3, before.rms_mm * 1e3, after.worst_mm * 1e3, after.rms_mm * 1e3);
  LONGS_EQUAL(41 * 31, after.points);  // the reference readings are no points of the surface
  CHECK(!cloud.drift.empty());
  CHECK(before.worst_mm > 0.015);
  // 0.58 um a reading, the first point's and two references' noise carried into every correction.
  CHECK(after.worst_mm <= 0.002 + 3.5 * 0.00058);
  CHECK(after.rms_mm <= 0.0012);
  // The scan file keeps the readings: one after every second line of 31 and one after the last.
  const ScanData data = read_scan_file(referenced);
  size_t references = 0;
  for (const auto& p : data.points) references += (p.flags & digitizer_PointFlag_POINT_REFERENCE) != 0;
  LONGS_EQUAL(16, references);
  // Each point's uncertainty gains the correction's.
  const PointCloud uncorrected_sigma = read_points(referenced, true);
  CHECK(cloud.sigma.has_value() && uncorrected_sigma.sigma.has_value());
  double gained = 0;
  for (size_t k = 0; k < cloud.points.size(); ++k) gained = std::fmax(gained, (*cloud.sigma)[k] - (*uncorrected_sigma.sigma)[k]);
  CHECK(gained > 0.0001);
  std::remove(plain.c_str());
  std::remove(referenced.c_str());
}

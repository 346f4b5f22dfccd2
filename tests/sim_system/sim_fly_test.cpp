// Scanning on the fly through the whole system: the host's capture, the sim: transport, the
// firmware's fly lines over a gauge that latches late, and the scan file read back as points, whose
// positions the latch-delay correction puts where the gauge read them (oracle: the part's shape).
#include <CppUTest/TestHarness.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "host/device/capture.h"
#include "host/device/session.h"
#include "host/scan/point_reader.h"
#include "host/scan/scan_file.h"
#include "host/transport/transport.h"
#include "hw/sim/parts.h"
#include "tests/support/scan_request.h"

namespace {

// A 40 x 30 mm fly scan of `part` (lines 1 mm apart, a point every 0.2 mm or closer) into a
// scan file, read back as the host's points.
dg::host::PointCloud fly_scan(const std::string& part, const std::string& options, uint32_t plunger_um_s = 0) {
  const std::string path = std::string(P_tmpdir) + "/dg_fly_" + std::to_string(getpid()) + "_" + part + ".scan";
  digitizer_ScanRequest request = dg::test::grid_request(9, 0, 40000000, 30000000, 200000, digitizer_ScanPattern_PATTERN_SERPENTINE);
  request.step_y_nm = 1000000;
  request.feed_um_s = 0;
  request.mode = digitizer_ScanMode_SCAN_MODE_FLY;
  request.plunger_follow_um_s = plunger_um_s;
  {
    auto transport = dg::host::open_transport("sim:part=" + part + ",seed=4,latch_delay_us=3000,latch_jitter_us=100" + options);
    dg::host::Session session(*transport);
    const digitizer_Hello hello = session.hello(5000);
    CHECK(hello.capabilities & digitizer_Capability_CAP_FLY_SCAN);
    dg::host::ScanFileWriter file = dg::host::ScanFileWriter::when_accepted(path, true);
    const dg::host::CaptureResult result = dg::host::capture_scan(session, hello, request, file, dg::host::CaptureOptions{});
    LONGS_EQUAL(digitizer_ScanEnd_SCAN_COMPLETED, result.done.reason);
  }
  dg::host::PointCloud cloud = dg::host::read_points(path);
  std::remove(path.c_str());
  return cloud;
}

double worst_error_um(const dg::host::PointCloud& cloud, dg::sim::PartKind kind) {
  dg::sim::Part part;
  part.kind = kind;
  double worst_um = 0;
  for (const auto& p : cloud.points) worst_um = std::fmax(worst_um, std::fabs(p.z - part.height_mm(p.x, p.y)) * 1e3);
  return worst_um;
}

}  // namespace

TEST_GROUP(SimFly){};

TEST(SimFly, TheSaddleOnTheFlyIsWithinTwoMicrometresOfItsShapeOnceTheLatchDelayIsOut) {
  const dg::host::PointCloud cloud = fly_scan("saddle", "");
  CHECK(cloud.points.size() >= 31 * 200);
  STRCMP_CONTAINS("latch delay", cloud.fly.c_str());
  STRCMP_CONTAINS("no reading lifted", cloud.fly.c_str());
  // 2 um and the gauge's noise (the bound): here the noise is the reading's 1 um step,
  // up to half a step. 1.66 um on a quiet machine; on a loaded one the host falls behind, lines
  // are flown again, and the delay estimate moves (1.79 um seen, and over 2 um once under the
  // sanitizers while other tests ran).
  const double worst_um = worst_error_um(cloud, dg::sim::PartKind::kSaddle);
  std::printf("\n  saddle on the fly: worst %.3f um from its shape; %s\n", worst_um, cloud.fly.c_str());
  CHECK(worst_um <= 2.5);
}

TEST(SimFly, TheCanisterOnTheFlyIsWithinTwoMicrometresOfItsShape) {
  const dg::host::PointCloud cloud = fly_scan("canister", "");
  CHECK(worst_error_um(cloud, dg::sim::PartKind::kCanister) <= 2.0);
}

TEST(SimFly, TheDomesFallingFlankIsLeftOutWhereTheSlowPlungerLifted) {
  // The device is told the plunger's real speed (5 mm/s), so what it flags is what lifted.
  const dg::host::PointCloud cloud = fly_scan("dome", ",plunger_mm_s=5", 5000);
  STRCMP_CONTAINS("lifted) left out", cloud.fly.c_str());
  // What is left is on the part: the readings the plunger took in the air are gone.
  CHECK(worst_error_um(cloud, dg::sim::PartKind::kDome) <= 20.0);
}

// The scan engine's readings on the simulated table: the median against outliers, the spread
// tolerance, settling until readings agree.
#include "firmware/core/scan_engine.h"

#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cstdlib>
#include <vector>

#include "tests/support/scan_request.h"
#include "tests/support/scan_rig.h"

namespace {

using Rig = dg::test::ScanRig;

dg::sim::SimConfig flat(double noise_um, double outliers) {
  dg::sim::SimConfig c;
  c.part.kind = dg::sim::PartKind::kFlat;  // 5 mm
  c.gauge.noise_sigma_mm = noise_um * 1e-3;
  c.gauge.outlier_rate = outliers;
  c.gauge.outlier_mm = 0.5;
  return c;
}

digitizer_ScanRequest line(uint32_t samples) {
  digitizer_ScanRequest r = dg::test::grid_request(1, 0, 20000000, 0, 1000000, digitizer_ScanPattern_PATTERN_RASTER);
  r.samples_per_point = samples;
  return r;
}

}  // namespace

TEST_GROUP(ScanEngine){};

TEST(ScanEngine, TheMedianOfFiveShrugsOffAnOutlierTheMeanDoesNot) {
  digitizer_ScanRequest r = line(5);
  Rig mean_rig(flat(0, 0.1));
  const std::vector<dg::PointSample> mean = mean_rig.run(r);
  r.median = true;
  Rig median_rig(flat(0, 0.1));
  const std::vector<dg::PointSample> median = median_rig.run(r);
  LONGS_EQUAL(21, median.size());
  int mean_off = 0;
  for (size_t i = 0; i < median.size(); ++i) {
    LONGS_EQUAL(5000000, median[i].z_nm);  // at most two outliers in five never move the median
    if (mean[i].z_nm != 5000000) ++mean_off;
  }
  CHECK(mean_off > 0);
}

TEST(ScanEngine, SamplesThatDisagreeAreRetakenOnceThenFlagged) {
  digitizer_ScanRequest r = line(4);
  r.spread_tolerance_nm = 2000;  // 2 um against 5 um noise: most points spread wider
  Rig rig(flat(5, 0));
  const std::vector<dg::PointSample> points = rig.run(r);
  int flagged = 0, retried = 0;
  for (const dg::PointSample& p : points) {
    if (p.flags & digitizer_PointFlag_POINT_SPREAD_HIGH) ++flagged;
    if (p.flags & digitizer_PointFlag_POINT_RETRIED) ++retried;
    if (p.flags & digitizer_PointFlag_POINT_SPREAD_HIGH) CHECK(p.flags & digitizer_PointFlag_POINT_RETRIED);
  }
  CHECK(flagged > 0);
  CHECK(retried >= flagged);
  // A generous tolerance flags nothing.
  r.spread_tolerance_nm = 100000;
  Rig calm(flat(5, 0));
  for (const dg::PointSample& p : calm.run(r)) LONGS_EQUAL(0, p.flags & (digitizer_PointFlag_POINT_SPREAD_HIGH | digitizer_PointFlag_POINT_RETRIED));
}

TEST(ScanEngine, SettlingReadsUntilTwoAgree) {
  digitizer_ScanRequest r = line(1);
  r.settle_tolerance_nm = 1000;
  Rig rig(flat(0, 0));
  const std::vector<dg::PointSample> points = rig.run(r);
  // A still gauge agrees at once: one settling reading, then the sample.
  LONGS_EQUAL(21 * 2, rig.board.gauge().frames_sent());
  for (const dg::PointSample& p : points) LONGS_EQUAL(0, p.flags & digitizer_PointFlag_POINT_SPREAD_HIGH);
  // A gauge that never settles within 0.1 um: flagged after eight readings, the point still taken.
  r.settle_tolerance_nm = 100;
  Rig noisy(flat(20, 0));
  const std::vector<dg::PointSample> restless = noisy.run(r);
  LONGS_EQUAL(21, restless.size());
  int flagged = 0;
  for (const dg::PointSample& p : restless) flagged += (p.flags & digitizer_PointFlag_POINT_SPREAD_HIGH) ? 1 : 0;
  CHECK(flagged > 10);
}

TEST(ScanEngine, ApproachingEveryPointFromOneSideCancelsBacklash) {
  // 0.1 mm of play and no compensation: on the serpentine's backward lines the table lags the
  // count by the play, unless each point is overshot and approached moving +x.
  for (uint32_t approach_nm : {0u, 500000u}) {
    dg::sim::SimConfig c = flat(0, 0);
    c.backlash_steps = 40;
    Rig rig(c);
    struct Where final : dg::PointSink {
      explicit Where(dg::sim::SimBoard& b) : board(b) {}
      bool accept(const dg::PointSample& p) override {
        worst = std::max<int64_t>(worst, std::llabs(board.table_x_steps() - p.x_nm / 2500));
        ++points;
        return true;
      }
      dg::sim::SimBoard& board;
      int64_t worst = 0;
      int points = 0;
    } where(rig.board);
    digitizer_ScanRequest r = dg::test::grid_request(1, 1000000, 5000000, 2000000, 1000000, digitizer_ScanPattern_PATTERN_SERPENTINE);
    r.approach_nm = approach_nm;
    const char* reason = "";
    CHECK(rig.scan.start(r, 1, 10000, &reason) == digitizer_FaultCode_FAULT_NONE);
    while (!rig.scan.finished()) {
      rig.scan.poll(where);
      if (!rig.scan.finished() && !rig.board.wait(rig.scan.deadline_us())) break;
    }
    LONGS_EQUAL(15, where.points);
    LONGS_EQUAL(approach_nm > 0 ? 0 : 40, where.worst);
  }
}

// Scanning on the fly on the simulated table: the feed the gauge's cycle sets, every point where the
// table was at its request, line flags, lifted readings flagged, and the requests it refuses.
#include <CppUTest/TestHarness.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <type_traits>
#include <vector>

#include "tests/support/scan_request.h"
#include "tests/support/scan_rig.h"

namespace {

// Lines of `length_mm` from x = 2 mm, `lines` of them 1 mm apart, a reading every 0.2 mm or closer.
digitizer_ScanRequest fly_lines(double length_mm, int lines) {
  digitizer_ScanRequest r = dg::test::grid_request(5, 2000000, 2000000 + static_cast<int32_t>(length_mm * 1e6),
                                                   (lines - 1) * 1000000, 200000, digitizer_ScanPattern_PATTERN_SERPENTINE);
  r.step_y_nm = 1000000;
  r.feed_um_s = 0;  // the gauge's cycle sets it
  r.mode = digitizer_ScanMode_SCAN_MODE_FLY;
  return r;
}

// One fly line across the dome's middle (y = 15 mm), told the plunger follows at 3 mm/s.
digitizer_ScanRequest across_the_dome() {
  digitizer_ScanRequest r = dg::test::grid_request(5, 0, 40000000, 15000000, 200000, digitizer_ScanPattern_PATTERN_SERPENTINE);
  r.y.min_nm = 15000000;
  r.feed_um_s = 0;
  r.mode = digitizer_ScanMode_SCAN_MODE_FLY;
  r.plunger_follow_um_s = 3000;
  return r;
}

dg::sim::SimConfig part(dg::sim::PartKind kind) {
  dg::sim::SimConfig c;
  c.part.kind = kind;
  return c;
}

}  // namespace

TEST_GROUP(FlyScan){};

TEST(FlyScan, ReadsEachLineBackToBackAtTheFeedTheGaugesCycleAllows) {
  dg::test::ScanRig rig(part(dg::sim::PartKind::kSaddle));
  const std::vector<dg::PointSample> points = rig.run(fly_lines(10, 3));
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_COMPLETED, rig.scan.end_reason());
  // The simulated Digimatic takes 5 ms to its first clock and 52 bits of 0.4 ms: 25.8 ms a reading.
  CHECK(rig.scan.gauge_cycle_us() >= 25800 && rig.scan.gauge_cycle_us() < 28000);
  std::vector<std::vector<dg::PointSample>> lines(3);
  for (const auto& p : points) {
    CHECK(p.line < 3);
    lines[p.line].push_back(p);
  }
  for (uint32_t l = 0; l < 3; ++l) {
    const auto& line = lines[l];
    // 10 mm at one reading per 0.2 mm or closer: 50 or more, and not more than 10 % over.
    CHECK(line.size() >= 50 && line.size() <= 56);
    CHECK(line.front().flags & digitizer_PointFlag_POINT_LINE_START);
    CHECK(line.back().flags & digitizer_PointFlag_POINT_LINE_END);
    const int direction = (l % 2) ? -1 : 1;
    for (size_t i = 0; i < line.size(); ++i) {
      LONGS_EQUAL(static_cast<long>(l) * 1000000, line[i].y_nm);
      CHECK(line[i].x_nm >= 2000000 && line[i].x_nm <= 12000000);
      if (i == 0) continue;
      const int32_t step = (line[i].x_nm - line[i - 1].x_nm) * direction;
      CHECK(step > 0 && step <= 200000);
      CHECK(line[i].seq == line[i - 1].seq + 1);
    }
    // The line's ends: within a reading's spacing of the extent's.
    const int32_t first = direction > 0 ? line.front().x_nm : line.back().x_nm;
    const int32_t last = direction > 0 ? line.back().x_nm : line.front().x_nm;
    CHECK(first - 2000000 <= 200000 && 12000000 - last <= 200000);
  }
}

TEST(FlyScan, EveryPointIsWhereTheTableWasWhenItsReadingWasRequested) {
  // A gauge that latches at the request: each reading is the part at the point's own position.
  dg::test::ScanRig rig(part(dg::sim::PartKind::kSaddle));
  const std::vector<dg::PointSample> points = rig.run(fly_lines(20, 2));
  CHECK(points.size() > 150);
  dg::sim::Part saddle;
  saddle.kind = dg::sim::PartKind::kSaddle;
  double worst_um = 0;
  for (const auto& p : points) {
    const double truth_mm = saddle.height_mm(p.x_nm * 1e-6, p.y_nm * 1e-6);
    worst_um = std::fmax(worst_um, std::fabs(p.z_nm * 1e-6 - truth_mm) * 1e3);
  }
  // The gauge's 1 um step rounds the reading: half of it, and nothing else.
  CHECK(worst_um <= 0.5 + 1e-9);
}

TEST(FlyScan, AGaugeThatLatchesLateShiftsTheReadingAlongTheMotionEachWayOpposite) {
  // 3 ms late at about 7.5 mm/s: 22 um along x, on the saddle's 0.05..0.054 slope about 1.1 um,
  // up on lines run towards +x and down on lines run back.
  dg::sim::SimConfig c = part(dg::sim::PartKind::kSaddle);
  c.gauge.latch_delay_us = 3000;
  dg::test::ScanRig rig(c);
  const std::vector<dg::PointSample> points = rig.run(fly_lines(20, 2));
  dg::sim::Part saddle;
  saddle.kind = dg::sim::PartKind::kSaddle;
  double sum_um[2] = {0, 0};
  int count[2] = {0, 0};
  for (const auto& p : points) {
    sum_um[p.line] += (p.z_nm * 1e-6 - saddle.height_mm(p.x_nm * 1e-6, p.y_nm * 1e-6)) * 1e3;
    ++count[p.line];
  }
  const double forward_um = sum_um[0] / count[0], back_um = sum_um[1] / count[1];
  CHECK(forward_um > 0.7 && forward_um < 1.5);
  CHECK(back_um < -0.7 && back_um > -1.5);
}

TEST(FlyScan, FlagsTheReadingsAPlungerTooSlowToFollowTheDomeTook) {
  // Across the dome's middle: its far flank falls away at up to 0.93 mm/mm, faster than a plunger
  // of 3 mm/s follows at about 7.5 mm/s of feed.
  dg::sim::SimConfig c = part(dg::sim::PartKind::kDome);
  c.plunger_mm_s = 3;
  dg::test::ScanRig rig(c);
  const std::vector<dg::PointSample> points = rig.run(across_the_dome());
  dg::sim::Part dome;
  dome.kind = dg::sim::PartKind::kDome;
  int in_air = 0, in_air_flagged = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const dg::PointSample& p = points[i];
    const double surface_mm = dome.height_mm(p.x_nm * 1e-6, p.y_nm * 1e-6);
    const double above_um = (p.z_nm * 1e-6 - surface_mm) * 1e3;
    const bool is_flagged = (p.flags & digitizer_PointFlag_POINT_LIFTED) != 0;
    if (above_um > 20) {
      ++in_air;
      in_air_flagged += is_flagged;
    }
    CHECK(above_um > -1);  // a lifted plunger reads high, never low
    if (is_flagged && above_um <= 2) {
      // On the part but flagged: the part itself fell at 80 % of the plunger's speed or faster
      // (less the gauge's 1 um rounding), so the plunger was at its limit there.
      const dg::PointSample& q = points[i - 1];
      const double fell_mm = dome.height_mm(q.x_nm * 1e-6, q.y_nm * 1e-6) - surface_mm;
      CHECK(fell_mm + 0.002 >= 0.8 * 3.0 * (p.t_us - q.t_us) * 1e-6);
    }
  }
  CHECK(in_air > 10);
  // Every reading 20 um or more in the air is flagged.
  LONGS_EQUAL(in_air, in_air_flagged);
}

TEST(FlyScan, RefusesWhatOnlyStopAndGoCanDo) {
  dg::test::ScanRig rig(part(dg::sim::PartKind::kFlat));
  const char* reason = "";
  digitizer_ScanRequest raster = fly_lines(10, 2);
  raster.pattern = digitizer_ScanPattern_PATTERN_RASTER;
  LONGS_EQUAL(digitizer_FaultCode_FAULT_BAD_REQUEST, rig.scan.start(raster, 1, 10000, &reason));
  STRCMP_CONTAINS("serpentine", reason);
  digitizer_ScanRequest samples = fly_lines(10, 2);
  samples.samples_per_point = 4;
  LONGS_EQUAL(digitizer_FaultCode_FAULT_BAD_REQUEST, rig.scan.start(samples, 1, 10000, &reason));
  STRCMP_CONTAINS("one reading", reason);
  digitizer_ScanRequest references = fly_lines(10, 2);
  references.reference_every_lines = 1;
  LONGS_EQUAL(digitizer_FaultCode_FAULT_BAD_REQUEST, rig.scan.start(references, 1, 10000, &reason));
  digitizer_ScanRequest unknown = fly_lines(10, 2);
  const std::underlying_type_t<digitizer_ScanMode> seven = 7;  // a mode the enum does not name, as off the wire
  std::memcpy(&unknown.mode, &seven, sizeof seven);
  LONGS_EQUAL(digitizer_FaultCode_FAULT_BAD_REQUEST, rig.scan.start(unknown, 1, 10000, &reason));
}

TEST(FlyScan, AnAbortMidLineKeepsEveryPointAlreadyRead) {
  dg::test::ScanRig rig(part(dg::sim::PartKind::kSaddle));
  const char* reason = "";
  CHECK(rig.scan.start(fly_lines(20, 2), 1, 10000, &reason) == digitizer_FaultCode_FAULT_NONE);
  dg::test::CollectPoints sink;
  // Until ten points are in, then abort: the point the engine held for its line-end flag follows.
  for (int guard = 0; guard < 1000000 && sink.points.size() < 10; ++guard) {
    rig.scan.poll(sink);
    rig.board.wait(rig.scan.deadline_us());
  }
  const uint32_t done_before = rig.scan.points_done();
  rig.scan.abort();
  for (int guard = 0; guard < 1000 && !rig.scan.finished(); ++guard) rig.scan.poll(sink);
  rig.scan.poll(sink);
  CHECK(rig.scan.finished());
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_ABORTED, rig.scan.end_reason());
  CHECK_FALSE(rig.scan.holding_point());
  LONGS_EQUAL(done_before + 1, rig.scan.points_done());
  LONGS_EQUAL(rig.scan.points_done(), sink.points.size());
  CHECK(sink.points.back().flags & digitizer_PointFlag_POINT_LINE_END);
  for (size_t i = 1; i < sink.points.size(); ++i) LONGS_EQUAL(sink.points[i - 1].seq + 1, sink.points[i].seq);
}

namespace {

// A sink whose ring is full while `full` says so: it takes nothing and has no room.
struct FullWhileTold final : dg::PointSink {
  bool accept(const dg::PointSample& p) override {
    if (full) return false;
    points.push_back(p);
    return true;
  }
  uint32_t room() const override { return full ? 0 : 1000; }
  bool full = false;
  std::vector<dg::PointSample> points;
};

}  // namespace

TEST(FlyScan, ALineTheRingFilledUpIsFlownAgainFromItsGap) {
  dg::test::ScanRig rig(part(dg::sim::PartKind::kSaddle));
  const char* reason = "";
  CHECK(rig.scan.start(fly_lines(20, 2), 1, 10000, &reason) == digitizer_FaultCode_FAULT_NONE);
  FullWhileTold sink;
  uint64_t full_until_us = 0;
  for (int guard = 0; guard < 10000000 && !rig.scan.finished(); ++guard) {
    // Full for half a second of table time once the first line has 30 points (about 4 mm).
    if (full_until_us == 0 && sink.points.size() == 30) {
      sink.full = true;
      full_until_us = rig.board.now_us() + 500000;
    }
    if (sink.full && rig.board.now_us() >= full_until_us) sink.full = false;
    rig.scan.poll(sink);
    if (!rig.scan.finished() && !rig.board.wait(sink.full ? full_until_us : rig.scan.deadline_us())) break;
  }
  CHECK(rig.scan.finished());
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_COMPLETED, rig.scan.end_reason());
  // Every line whole: no two neighbours further apart than two steps, one way, numbered in order.
  size_t line0 = 0;
  for (size_t i = 1; i < sink.points.size(); ++i) {
    const dg::PointSample& a = sink.points[i - 1];
    const dg::PointSample& b = sink.points[i];
    LONGS_EQUAL(a.seq + 1, b.seq);
    if (a.line != b.line) continue;
    line0 += a.line == 0;
    const int32_t step = (b.x_nm - a.x_nm) * (a.line % 2 ? -1 : 1);
    CHECK(step > 0 && step <= 400000);
  }
  CHECK(line0 >= 100);  // 20 mm at 0.2 mm or closer
  // The first line ended at the extent's far end, flagged.
  for (size_t i = 0; i < sink.points.size(); ++i) {
    if (sink.points[i].line == 0 && (sink.points[i].flags & digitizer_PointFlag_POINT_LINE_END)) {
      CHECK(sink.points[i].x_nm >= 22000000 - 200000);
    }
  }
}

TEST(FlyScan, EachScanTimesTheGaugeAfreshForItsOwnStep) {
  dg::test::ScanRig rig(part(dg::sim::PartKind::kFlat));
  rig.run(fly_lines(10, 2));
  const uint32_t fine_rate = rig.scan.fly_rate_steps_s();
  digitizer_ScanRequest coarse = fly_lines(10, 2);
  coarse.step_x_nm = 400000;  // a point every 0.4 mm: twice the feed
  const std::vector<dg::PointSample> points = rig.run(coarse);
  DOUBLES_EQUAL(2.0, static_cast<double>(rig.scan.fly_rate_steps_s()) / fine_rate, 0.02);
  for (size_t i = 1; i < points.size(); ++i) {
    if (points[i].line == points[i - 1].line) CHECK(std::abs(points[i].x_nm - points[i - 1].x_nm) <= 400000);
  }
}

TEST(FlyScan, AGaugeThatFailsWhileTimedIsAskedAgain) {
  // Every frame loses one clock edge: each reading fails, the timing reading too; it is asked again,
  // and after the retries the scan ends on the gauge's fault instead of running its lines unread.
  dg::sim::SimConfig c = part(dg::sim::PartKind::kFlat);
  c.gauge.drop_rising_edge = 10;
  dg::test::ScanRig rig(c);
  rig.run(fly_lines(10, 2));
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_FAULTED, rig.scan.end_reason());
  LONGS_EQUAL(0, rig.scan.points_done());
}

TEST(FlyScan, AReadingInTheAirRightAfterALinesGapIsFlaggedToo) {
  // The dome's falling flank with a slow plunger, and the ring full for half a second while the
  // table is over it: the line is flown again from its gap, and the first readings after the gap
  // are judged against the readings just before them in that flight, not against the point kept
  // seconds earlier (against which one in the air fell too slowly to be flagged).
  dg::sim::SimConfig c = part(dg::sim::PartKind::kDome);
  c.plunger_mm_s = 3;
  dg::test::ScanRig rig(c);
  const digitizer_ScanRequest r = across_the_dome();
  const char* reason = "";
  CHECK(rig.scan.start(r, 1, 10000, &reason) == digitizer_FaultCode_FAULT_NONE);
  dg::sim::Part dome;
  dome.kind = dg::sim::PartKind::kDome;
  FullWhileTold sink;
  uint64_t full_until_us = 0;
  bool gap_in_air = false;
  for (int guard = 0; guard < 10000000 && !rig.scan.finished(); ++guard) {
    // Full once the kept point is in the air over the flank.
    if (full_until_us == 0 && !sink.points.empty()) {
      const dg::PointSample& p = sink.points.back();
      if ((p.z_nm * 1e-6 - dome.height_mm(p.x_nm * 1e-6, p.y_nm * 1e-6)) * 1e3 > 50) {
        sink.full = gap_in_air = true;
        full_until_us = rig.board.now_us() + 500000;
      }
    }
    if (sink.full && rig.board.now_us() >= full_until_us) sink.full = false;
    rig.scan.poll(sink);
    if (!rig.scan.finished() && !rig.board.wait(sink.full ? full_until_us : rig.scan.deadline_us())) break;
  }
  CHECK(rig.scan.finished());
  CHECK(gap_in_air);
  int in_air = 0, in_air_flagged = 0;
  for (const dg::PointSample& p : sink.points) {
    const double above_um = (p.z_nm * 1e-6 - dome.height_mm(p.x_nm * 1e-6, p.y_nm * 1e-6)) * 1e3;
    if (above_um > 20) {
      ++in_air;
      in_air_flagged += (p.flags & digitizer_PointFlag_POINT_LIFTED) != 0;
    }
  }
  CHECK(in_air > 10);
  LONGS_EQUAL(in_air, in_air_flagged);
}

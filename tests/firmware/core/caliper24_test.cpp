// The 24-bit caliper protocol: the decoder bit by bit, and the pin-level reader against the
// simulated instrument (values, inches, a lost clock edge, a silent instrument).
#include "firmware/core/caliper24.h"

#include <CppUTest/TestHarness.h>

#include "hw/sim/sim_board.h"

namespace {

struct Bench {
  explicit Bench(dg::sim::SimConfig config) : board(config, nullptr), reader(board, dg::CaliperTiming{}) { reader.attach(); }
  dg::Probe::State read() {
    CHECK(reader.start() == dg::Status::kOk);
    while (reader.poll() == dg::Probe::State::kReading) {
      if (!board.wait(reader.deadline_us())) break;
    }
    return reader.poll();
  }
  dg::sim::SimBoard board;
  dg::Caliper24Reader reader;
};

dg::sim::SimConfig caliper_over_flat(double offset_mm) {
  dg::sim::SimConfig c;
  c.caliper = true;
  c.part.kind = dg::sim::PartKind::kFlat;  // 5 mm
  c.part.offset_mm = offset_mm;
  return c;
}

}  // namespace

TEST_GROUP(Caliper24){};

TEST(Caliper24, DecodesMagnitudeSignAndUnit) {
  dg::CaliperReading r;
  CHECK(dg::caliper24_decode(1234, &r) == dg::Status::kOk);
  LONGS_EQUAL(1234, r.counts);
  CHECK(!r.inch);
  LONGS_EQUAL(12340000, dg::caliper24_to_nm(r));
  CHECK(dg::caliper24_decode(1234u | 1u << 20, &r) == dg::Status::kOk);
  LONGS_EQUAL(-1234, r.counts);
  CHECK(dg::caliper24_decode(2000u | 1u << 23, &r) == dg::Status::kOk);  // 1 inch
  CHECK(r.inch);
  LONGS_EQUAL(25400000, dg::caliper24_to_nm(r));
}

TEST(Caliper24, RefusesBitsTheFormatDoesNotUse) {
  dg::CaliperReading r;
  CHECK(dg::caliper24_decode(1u << 21, &r) == dg::Status::kBadEncoding);
  CHECK(dg::caliper24_decode(1u << 22, &r) == dg::Status::kBadEncoding);
  CHECK(dg::caliper24_decode(1u << 24, &r) == dg::Status::kBadEncoding);
}

TEST(Caliper24, ReadsTheInstrumentAtThePinLevel) {
  Bench bench(caliper_over_flat(7.3456));  // 12.3456 mm, shown to 0.01 mm
  CHECK(bench.read() == dg::Probe::State::kDone);
  LONGS_EQUAL(12350000, bench.reader.value_nm());
  // The instrument keeps its own 8 Hz schedule: a second read waits for its next frame.
  const uint64_t before = bench.board.now_ns();
  CHECK(bench.read() == dg::Probe::State::kDone);
  CHECK(bench.board.now_ns() - before <= 130000000u);
}

TEST(Caliper24, ReadsNegativeValuesAndInches) {
  Bench negative(caliper_over_flat(-7.5));  // -2.5 mm
  CHECK(negative.read() == dg::Probe::State::kDone);
  LONGS_EQUAL(-2500000, negative.reader.value_nm());
  dg::sim::SimConfig c = caliper_over_flat(20.4);  // 25.4 mm = 1 inch
  c.gauge.inch = true;
  Bench inch(c);
  CHECK(inch.read() == dg::Probe::State::kDone);
  CHECK(inch.reader.reading().inch);
  LONGS_EQUAL(25400000, inch.reader.value_nm());
}

TEST(Caliper24, ALostClockEdgeIsAnErrorNeverAValue) {
  for (int bit : {0, 7, 23}) {
    dg::sim::SimConfig c = caliper_over_flat(1.0);
    c.gauge.drop_rising_edge = bit;
    Bench bench(c);
    CHECK(bench.read() == dg::Probe::State::kFailed);
    CHECK(bench.reader.error() == dg::Status::kBadEncoding);
  }
}

TEST(Caliper24, ASilentInstrumentTimesOut) {
  dg::sim::SimConfig c = caliper_over_flat(1.0);
  c.gauge.mute = true;
  Bench bench(c);
  CHECK(bench.read() == dg::Probe::State::kFailed);
  CHECK(bench.reader.error() == dg::Status::kTimeout);
}

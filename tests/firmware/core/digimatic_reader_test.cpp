// The firmware's pin-level Digimatic reader against the simulated gauge's pins.
#include "firmware/core/digimatic_reader.h"

#include <CppUTest/TestHarness.h>

#include "hw/sim/sim_board.h"

namespace {

struct Bench {
  explicit Bench(dg::sim::SimConfig config) : board(config, nullptr), reader(board, timing()) {
    reader.attach();
  }
  static dg::DigimaticTiming timing() {
    dg::DigimaticTiming t;
    t.first_clock_timeout_us = 50000;
    t.bit_timeout_us = 5000;
    return t;
  }
  dg::DigimaticReader::State read() {
    CHECK(reader.start() == dg::Status::kOk);
    while (reader.poll() == dg::DigimaticReader::State::kReading) {
      if (!board.wait(reader.deadline_us())) break;
    }
    return reader.poll();
  }
  dg::sim::SimBoard board;
  dg::DigimaticReader reader;
};

dg::sim::SimConfig flat(double offset_mm) {
  dg::sim::SimConfig c;
  c.part.kind = dg::sim::PartKind::kFlat;  // 5 mm
  c.part.offset_mm = offset_mm;
  return c;
}

}  // namespace

TEST_GROUP(DigimaticReader){};

TEST(DigimaticReader, ReadsAPositiveMillimetreValue) {
  Bench bench(flat(7.3456));  // 12.3456 mm, shown to 1 um
  CHECK(bench.read() == dg::DigimaticReader::State::kDone);
  CHECK(dg::digimatic_to_nm(bench.reader.reading()) == 12346000);
  LONGS_EQUAL(52, bench.reader.bits_received());
}

TEST(DigimaticReader, ReadsANegativeValue) {
  Bench bench(flat(-7.5));  // -2.5 mm
  CHECK(bench.read() == dg::DigimaticReader::State::kDone);
  CHECK(dg::digimatic_to_nm(bench.reader.reading()) == -2500000);
}

TEST(DigimaticReader, ReadsInches) {
  dg::sim::SimConfig config = flat(0.0);
  config.gauge.inch = true;
  Bench bench(config);
  CHECK(bench.read() == dg::DigimaticReader::State::kDone);
  CHECK(bench.reader.reading().unit == dg::GaugeUnit::kInch);
  // 5 mm = 0.19685 in, shown as 0.1969 in = 5.00126 mm.
  LONGS_EQUAL(1969, bench.reader.reading().value);
  CHECK(dg::digimatic_to_nm(bench.reader.reading()) == 5001260);
}

TEST(DigimaticReader, MissingClockEdgeIsAnErrorNeverAWrongNumber) {
  for (int drop : {0, 1, 17, 30, 51}) {
    dg::sim::SimConfig config = flat(0.0);
    config.gauge.drop_rising_edge = drop;
    Bench bench(config);
    CHECK(bench.read() == dg::DigimaticReader::State::kFailed);
    CHECK(bench.reader.error() == dg::Status::kTimeout);
    LONGS_EQUAL(51, bench.reader.bits_received());
  }
}

TEST(DigimaticReader, SilentGaugeTimesOut) {
  dg::sim::SimConfig config = flat(0.0);
  config.gauge.mute = true;
  Bench bench(config);
  CHECK(bench.read() == dg::DigimaticReader::State::kFailed);
  CHECK(bench.reader.error() == dg::Status::kTimeout);
  LONGS_EQUAL(0, bench.reader.bits_received());
}

TEST(DigimaticReader, ReleasesRequestAfterTheFirstClock) {
  Bench bench(flat(0.0));
  CHECK(bench.read() == dg::DigimaticReader::State::kDone);
  CHECK_FALSE(bench.board.read_pin(dg::hal::Pin::kGaugeReq));
  LONGS_EQUAL(1, bench.board.gauge().frames_sent());
}

TEST(DigimaticReader, ARetryOnAGaugeThatKeepsDroppingAnEdgeFailsAgain) {
  // drop_rising_edge damages every frame: the reader starts again after a failure,
  // and the retry fails the same way instead of yielding a number.
  dg::sim::SimConfig config = flat(1.0);
  config.gauge.drop_rising_edge = 10;
  Bench bench(config);
  CHECK(bench.read() == dg::DigimaticReader::State::kFailed);
  CHECK(bench.read() == dg::DigimaticReader::State::kFailed);
}

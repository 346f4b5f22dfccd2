// The gauge model clocked in real time: changes come when due, and a late player shifts the rest
// of the frame rather than bunching CK changes together.
#include <CppUTest/TestHarness.h>

#include "hw/hil/real_time_gauge.h"

using dg::hil::RealTimeGauge;

namespace {
dg::sim::GaugeConfig timing() {
  dg::sim::GaugeConfig config;
  config.request_to_clock_us = 5000;
  config.clock_low_us = config.clock_high_us = 200;
  return config;
}
}  // namespace

TEST_GROUP(RealTimeGauge) {};

TEST(RealTimeGauge, ChangesComeWhenDueOnThePlayersClock) {
  RealTimeGauge gauge(timing(), 1000000000);
  UNSIGNED_LONGS_EQUAL(UINT64_MAX, gauge.due_ns());
  gauge.set_request(true, 1000000000, 1.234);
  UNSIGNED_LONGS_EQUAL(1005000000, gauge.due_ns());
  CHECK_FALSE(gauge.advance(1004999999));
  CHECK(gauge.clock());  // CK idles high
  CHECK(gauge.advance(1005000000));
  CHECK_FALSE(gauge.clock());
  UNSIGNED_LONGS_EQUAL(1005200000, gauge.due_ns());
}

TEST(RealTimeGauge, ALatePlayerShiftsTheRestOfTheFrameAndNeverShortensAPhase) {
  RealTimeGauge gauge(timing(), 0);
  gauge.set_request(true, 0, 1.234);
  CHECK(gauge.advance(5000000 + 3000000));  // the first fall, 3 ms late
  UNSIGNED_LONGS_EQUAL(8200000, gauge.due_ns());
  uint64_t last = 8000000;
  int changes = 1;
  // Wake late every time: each phase is still at least 200 us long.
  while (gauge.due_ns() != UINT64_MAX) {
    const uint64_t now = gauge.due_ns() + 70000;
    CHECK(gauge.advance(now));
    CHECK(now - last >= 200000);
    last = now;
    ++changes;
  }
  LONGS_EQUAL(2 * dg::kDigimaticBits, changes);
  UNSIGNED_LONGS_EQUAL(1, gauge.model().frames_sent());
}

// The boards' step schedule: chained while on time, restarted from the tick when late, so no two
// steps ever come closer together than the step generator asked; on a wrapping 32-bit counter too.
#include "firmware/hal/step_schedule.h"

#include <CppUTest/TestHarness.h>

#include <cstdint>

using dg::hal::next_step_due;
using dg::hal::step_late;

namespace {
constexpr uint64_t kLateNs = 50000;
}

TEST_GROUP(StepSchedule){};

TEST(StepSchedule, ASmallLatenessDoesNotAccumulate) {
  // Due at 1000 us, ran 20 us late: the next is still due 125 us after the due time.
  UNSIGNED_LONGS_EQUAL(1125000, next_step_due<uint64_t>(1000000, 1020000, 125000, kLateNs));
  CHECK_FALSE(step_late<uint64_t>(1000000, 1020000, kLateNs));
}

TEST(StepSchedule, ALateTickRestartsFromNowInsteadOfBurstingTheMissedSteps) {
  // Ran 10 ms late: chaining would make the next ten steps due at once.
  UNSIGNED_LONGS_EQUAL(11125000, next_step_due<uint64_t>(1000000, 11000000, 125000, kLateNs));
  CHECK(step_late<uint64_t>(1000000, 11000000, kLateNs));
}

TEST(StepSchedule, StepsAreNeverCloserThanAsked) {
  uint64_t due = 0, now = 0, last_now = 0;
  const uint64_t wakeups[] = {3000, 80000, 1000, 200000, 0, 60000, 51000};
  bool first = true;
  for (uint64_t lateness : wakeups) {
    now = due + lateness;  // the tick runs this late
    if (!first) CHECK(now - last_now >= 125000 - kLateNs);  // jitter below the late bound only
    first = false;
    last_now = now;
    due = next_step_due<uint64_t>(due, now, 125000, kLateNs);
    CHECK(due >= now + 125000 - kLateNs);
  }
}

TEST(StepSchedule, AWrappingHardwareCounterKeepsTheScheduleAcrossItsWrap) {
  // A 32-bit counter at 96 MHz, 96 ticks (1 us) of allowed lateness, a step every 12,000 ticks.
  const uint32_t due = 0xFFFFFF00u;
  // On time across the wrap: chained.
  UNSIGNED_LONGS_EQUAL(0xFFFFFF00u + 12000u, next_step_due<uint32_t>(due, 0xFFFFFF10u, 12000, 96));
  // 300 ticks late, past the wrap: restarted from the tick, not chained into a burst.
  CHECK(step_late<uint32_t>(due, 0x0000002Cu, 96));
  UNSIGNED_LONGS_EQUAL(0x0000002Cu + 12000u, next_step_due<uint32_t>(due, 0x0000002Cu, 12000, 96));
  // A counter read a little before the compare (it cannot run early) is not "late by 2^32".
  CHECK_FALSE(step_late<uint32_t>(due, 0xFFFFFEF0u, 96));
}

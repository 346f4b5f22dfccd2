// The Linux-gadget board's step schedule: chained while on time, restarted from now when late, so
// no two steps ever come closer together than the step generator asked.
#include <CppUTest/TestHarness.h>

#include "hw/boards/linux-gadget/step_schedule.h"

using dg::gadget::next_step_due;
using dg::gadget::step_late;

TEST_GROUP(StepSchedule) {};

TEST(StepSchedule, ASmallLatenessDoesNotAccumulate) {
  // Due at 1000 us, ran 20 us late: the next is still due 125 us after the due time.
  UNSIGNED_LONGS_EQUAL(1125000, next_step_due(1000000, 1020000, 125000));
  CHECK_FALSE(step_late(1000000, 1020000));
}

TEST(StepSchedule, ALateTickRestartsFromNowInsteadOfBurstingTheMissedSteps) {
  // Ran 10 ms late: chaining would make the next ten steps due at once.
  UNSIGNED_LONGS_EQUAL(11125000, next_step_due(1000000, 11000000, 125000));
  CHECK(step_late(1000000, 11000000));
}

TEST(StepSchedule, StepsAreNeverCloserThanAsked) {
  uint64_t due = 0, now = 0, last_now = 0;
  const uint64_t wakeups[] = {3000, 80000, 1000, 200000, 0, 60000, 51000};
  bool first = true;
  for (uint64_t lateness : wakeups) {
    now = due + lateness;  // the process wakes this late
    if (!first) CHECK(now - last_now >= 125000 - 50000);  // jitter below the late bound only
    first = false;
    last_now = now;
    due = next_step_due(due, now, 125000);
    CHECK(due >= now + 125000 - 50000);
  }
}

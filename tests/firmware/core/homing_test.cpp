// Homing and hard limits on the simulated table: the switch point becomes the machine position,
// a closed switch stops an axis before its next step, the e-stop stops everything.
#include "firmware/core/homing.h"

#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cstdlib>

#include "hw/sim/sim_board.h"

namespace {

struct Rig {
  explicit Rig(dg::sim::SimConfig config) : board(config, nullptr), motion(board, dg::MotionConfig{}), homing(motion) {}
  // Runs until homing ends (or the time runs out).
  void home() {
    homing.start();
    while (homing.active()) {
      homing.poll();
      if (!motion.busy() && !homing.active()) break;
      if (motion.busy() && !board.wait(UINT64_MAX)) break;
    }
  }
  dg::sim::SimBoard board;
  dg::StepGenerator motion;
  dg::Homing homing;
};

dg::sim::SimConfig table_at(int32_t x, int32_t y) {
  dg::sim::SimConfig c;
  c.start_x_steps = x;
  c.start_y_steps = y;
  return c;
}

}  // namespace

TEST_GROUP(Homing){};

TEST(Homing, FindsTheSwitchesFromAnywhereAndAgreesWithTheTable) {
  // The firmware wakes believing (0, 0); the table is 12.5 mm, 7.5 mm from its switches.
  for (auto start : {table_at(5000, 3000), table_at(0, 0), table_at(-3, 40)}) {
    Rig rig(start);
    rig.home();
    CHECK(rig.homing.done());
    const dg::MotionConfig c;
    LONGS_EQUAL(c.home_pull_off_steps, rig.motion.x_steps());
    LONGS_EQUAL(c.home_pull_off_steps, rig.motion.y_steps());
    // The firmware's steps are the table's: the scan's coordinates are exact after homing.
    LONGS_EQUAL(rig.motion.x_steps(), rig.board.table_x_steps());
    LONGS_EQUAL(rig.motion.y_steps(), rig.board.table_y_steps());
    LONGS_EQUAL(0, rig.board.lost_steps());
  }
}

TEST(Homing, FailsWhenASwitchIsMissing) {
  dg::sim::SimConfig c = table_at(2000, 2000);
  c.limit_switches = false;
  Rig rig(c);
  rig.home();
  CHECK(rig.homing.failed());
  STRCMP_CONTAINS("x min switch was not found", rig.homing.failure());
}

TEST(Homing, AClosedSwitchStopsTheAxisBeforeItsNextStep) {
  // The firmware believes x = 1000 steps; the table is at 100. A move to 0 runs into the switch.
  Rig rig(table_at(100, 500));
  rig.motion.set_position(1000, 500);
  CHECK(rig.motion.move_to(0, 500, 0) == dg::Status::kOk);
  while (rig.motion.busy() && rig.board.wait(UINT64_MAX)) {
  }
  CHECK(rig.motion.trip() == dg::Trip::kLimitX);
  // One step past the switch's closing point (table < 0) and not one more.
  LONGS_EQUAL(-1, rig.board.table_x_steps());
  LONGS_EQUAL(1000 - 101, rig.motion.x_steps());
}

TEST(Homing, TheEstopStopsAMoveAtOnce) {
  dg::sim::SimConfig c = table_at(0, 0);
  c.estop_at_ns = 50000000;  // 50 ms into a 10 mm move
  c.estop_for_ns = 1000000000;
  Rig rig(c);
  CHECK(rig.motion.move_to(4000, 0, 0) == dg::Status::kOk);
  while (rig.motion.busy() && rig.board.wait(UINT64_MAX)) {
  }
  CHECK(rig.motion.trip() == dg::Trip::kEstop);
  CHECK(rig.motion.x_steps() < 4000);
  LONGS_EQUAL(rig.motion.x_steps(), rig.board.table_x_steps());
}

TEST(Homing, BacklashCompensationKeepsTheTableWhereTheStepsSay) {
  // 0.1 mm of play in both screws. With compensation every reversal takes it up uncounted; without,
  // the table lags the count by the play after each reversal.
  for (uint32_t compensation : {40u, 0u}) {
    dg::sim::SimConfig c = table_at(3000, 3000);
    c.backlash_steps = 40;
    dg::sim::SimBoard board(c, nullptr);
    dg::MotionConfig m;
    m.backlash_x_steps = m.backlash_y_steps = compensation;
    dg::StepGenerator motion(board, m);
    dg::Homing homing(motion);
    homing.start();
    while (homing.active()) {
      homing.poll();
      if (motion.busy() && !board.wait(UINT64_MAX)) break;
    }
    CHECK(homing.done());
    int64_t worst = 0;
    const int32_t targets[][2] = {{4000, 400}, {2000, 1200}, {3000, 600}, {1000, 1000}, {1500, 200}};
    for (const auto& t : targets) {
      CHECK(motion.move_to(t[0], t[1], 0) == dg::Status::kOk);
      while (motion.busy() && board.wait(UINT64_MAX)) {
      }
      worst = std::max<int64_t>(worst, std::llabs(board.table_x_steps() - motion.x_steps()));
      worst = std::max<int64_t>(worst, std::llabs(board.table_y_steps() - motion.y_steps()));
    }
    if (compensation > 0) {
      LONGS_EQUAL(0, worst);
    } else {
      LONGS_EQUAL(40, worst);
    }
  }
}

// Homing and hard limits on the simulated table: the switch point becomes the machine position,
// a tripped switch stops an axis before its next step, the e-stop stops everything; unwired,
// jammed, bouncing, noisy and cut switches (normally closed, as the docs wire them).
#include "firmware/core/homing.h"

#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cstdlib>
#include <string>

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

// Homes a table 5 mm from its switches wired as given; how it ended.
struct Failed {
  bool failed;
  std::string why;
  uint64_t lost_steps;
};
Failed home_with(dg::sim::SwitchWiring wiring) {
  dg::sim::SimConfig c = table_at(2000, 2000);
  c.switches = wiring;
  Rig rig(c);
  rig.home();
  return {rig.homing.failed(), rig.homing.failure(), rig.board.lost_steps()};
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

TEST(Homing, AnUnwiredSwitchFailsInsteadOfHomingWhereverTheTableIs) {
  // Normally closed and unplugged: the input reads tripped everywhere. The seek "finds" it at
  // once; backing off 2 mm does not clear it, so homing fails instead of calling this spot home.
  const Failed f = home_with(dg::sim::SwitchWiring::kOpen);
  CHECK(f.failed);
  STRCMP_CONTAINS("x switch still tripped 2 mm off it", f.why.c_str());
  LONGS_EQUAL(0, f.lost_steps);
}

TEST(Homing, AJammedSwitchFailsAfterTheWholeTravel) {
  const Failed f = home_with(dg::sim::SwitchWiring::kStuckClosed);
  CHECK(f.failed);
  STRCMP_CONTAINS("x switch not found over the travel", f.why.c_str());
}

TEST(Homing, BouncingContactsAndSpikesOnTheInputsHomeToTheCleanStep) {
  // Contacts that chatter for 2 ms at the edge, and a 2 us spike on every limit and e-stop input
  // each millisecond: homing still ends where clean switches put it, with the steps the table's.
  Rig clean(table_at(5000, 3000));
  clean.home();
  CHECK(clean.homing.done());
  dg::sim::SimConfig c = table_at(5000, 3000);
  c.switch_bounce_ns = 2000000;
  c.glitch_period_ns = 1000000;
  Rig noisy(c);
  noisy.home();
  CHECK_TEXT(noisy.homing.done(), noisy.homing.failure());
  LONGS_EQUAL(clean.board.table_x_steps(), noisy.board.table_x_steps());
  LONGS_EQUAL(clean.board.table_y_steps(), noisy.board.table_y_steps());
  LONGS_EQUAL(noisy.motion.x_steps(), noisy.board.table_x_steps());
  LONGS_EQUAL(noisy.motion.y_steps(), noisy.board.table_y_steps());
}

TEST(Homing, SpikesOnTheInputsDoNotStopAMove) {
  // A 10 mm move reads the e-stop before each of its 4,000 steps; with a spike every millisecond
  // some reads land on one, and a single read would stop the move.
  dg::sim::SimConfig c = table_at(0, 0);
  c.glitch_period_ns = 1000000;
  Rig rig(c);
  rig.motion.set_position(0, 0);
  CHECK(rig.motion.move_to(4000, 0, 0) == dg::Status::kOk);
  while (rig.motion.busy() && rig.board.wait(UINT64_MAX)) {
  }
  CHECK(rig.motion.trip() == dg::Trip::kNone);
  LONGS_EQUAL(4000, rig.board.table_x_steps());
}

TEST(Homing, ACutWireStopsMovesTowardsTheSwitchAndFailsTheNextHoming) {
  Rig rig(table_at(3000, 3000));
  rig.home();
  CHECK(rig.homing.done());
  // The x switch's wire is cut 50 ms into a move towards it: the open circuit reads tripped.
  rig.board.cut_x_wire_at(rig.board.now_ns() + 50000000);
  CHECK(rig.motion.move_to(0, 400, 0) == dg::Status::kOk);
  while (rig.motion.busy() && rig.board.wait(UINT64_MAX)) {
  }
  CHECK(rig.motion.trip() == dg::Trip::kLimitX);
  CHECK(rig.motion.x_steps() > 0);
  LONGS_EQUAL(rig.motion.x_steps(), rig.board.table_x_steps());
  rig.home();
  CHECK(rig.homing.failed());
  STRCMP_CONTAINS("x switch still tripped 2 mm off it", rig.homing.failure());
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
  // The step interrupt cut the drivers; no step pulse went to a driver that was off.
  CHECK_FALSE(rig.board.drivers_on());
  LONGS_EQUAL(0, rig.board.steps_without_drivers());
  LONGS_EQUAL(rig.motion.x_steps(), rig.board.table_x_steps());
}

TEST(Homing, TheEstopStopsTheTableWithinAQuarterMillisecondWhileStepsAreMillisecondsApart) {
  // Pressed 0.5 ms into a move from rest, whose first step comes 5 ms in: the step interrupt used to
  // see it only then (4.5 ms). It now also wakes every 250 us between steps to read the e-stop.
  dg::sim::SimConfig c = table_at(0, 0);
  c.estop_at_ns = 500000;
  c.estop_for_ns = 1000000000;
  Rig rig(c);
  CHECK(rig.motion.move_to(4000, 0, 0) == dg::Status::kOk);
  while (rig.motion.busy() && rig.board.wait(UINT64_MAX)) {
  }
  CHECK(rig.motion.trip() == dg::Trip::kEstop);
  CHECK_FALSE(rig.board.drivers_on());
  CHECK(rig.board.drivers_cut_ns() - c.estop_at_ns <= dg::StepGenerator::kSafetyReadNs + dg::StepGenerator::kConfirmNs);
  LONGS_EQUAL(0, rig.board.table_x_steps());
}

// The e-stop's edge interrupt: pressed anywhere in a move, at rest or at full speed, the drivers
// go off 20 us after the press (its confirming read), no step pulse reaches them after, and the
// move ends at its next tick with the table where the steps say.
TEST(Homing, TheEstopsEdgeCutsTheDriversTwentyMicrosecondsAfterThePressAtAnySpeed) {
  for (uint64_t press_us : {500ull, 20000ull, 150000ull, 400000ull}) {
    dg::sim::SimConfig c = table_at(0, 0);
    c.estop_at_ns = press_us * 1000;
    c.estop_for_ns = 1000000000;
    Rig rig(c);
    rig.motion.attach_estop();
    CHECK(rig.motion.move_to(4000, 0, 0) == dg::Status::kOk);
    while (rig.motion.busy() && rig.board.wait(UINT64_MAX)) {
    }
    CHECK(rig.motion.trip() == dg::Trip::kEstop);
    CHECK_FALSE(rig.board.drivers_on());
    LONGS_EQUAL(c.estop_at_ns + dg::StepGenerator::kConfirmNs, rig.board.drivers_cut_ns());
    LONGS_EQUAL(0, rig.board.steps_without_drivers());
    LONGS_EQUAL(rig.motion.x_steps(), rig.board.table_x_steps());
  }
}

// A 2 us spike on the e-stop cable every 3 ms: each edge interrupt reads the input again 20 us
// later, finds it released, and the move goes on to its end with the drivers on.
TEST(Homing, SpikesOnTheEstopEdgeNeitherCutTheDriversNorStopTheMove) {
  dg::sim::SimConfig c = table_at(0, 0);
  c.glitch_period_ns = 3000000;
  Rig rig(c);
  rig.motion.attach_estop();
  CHECK(rig.motion.move_to(4000, 0, 0) == dg::Status::kOk);
  while (rig.motion.busy() && rig.board.wait(UINT64_MAX)) {
  }
  CHECK(rig.motion.trip() == dg::Trip::kNone);
  CHECK(rig.board.drivers_on());
  LONGS_EQUAL(4000, rig.board.table_x_steps());
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

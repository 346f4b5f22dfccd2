// The Black Pill board's own code (board.cpp, pins.cpp) and the firmware core's step generator on
// it, run against the register-level fake of the STM32F411: pins, edges, the step timer, the clock
// across its wrap, the e-stop's path to the drivers, the watchdog and the reset cause.
#include "hw/boards/stm32f411/board.h"

#include <CppUTest/TestHarness.h>

#include <cstdint>
#include <functional>
#include <algorithm>
#include <memory>
#include <vector>

#include "firmware/core/digimatic_reader.h"
#include "firmware/core/homing.h"
#include "firmware/core/step_generator.h"
#include "hw/sim/digimatic_gauge.h"
#include "hw/boards/stm32f411/pins.h"
#include "hw/boards/stm32f411/registers.h"
#include "tests/support/black_pill.h"
#include "tests/support/fake_stm32.h"

using dg::hal::Pin;
using dg::test::BlackPill;
using dg::test::FakeStm32;
namespace stm32 = dg::stm32;

namespace {

constexpr uint64_t kCyclesPerUs = FakeStm32::kCoreHz / 1000000;

struct Calls {
  std::vector<uint64_t> at;
  FakeStm32* chip = nullptr;
  uint32_t interval_ns = 0;
  size_t limit = 0;
  static uint32_t tick(void* self) {
    Calls& c = *static_cast<Calls*>(self);
    c.at.push_back(c.chip->cycles());
    return c.at.size() < c.limit ? c.interval_ns : 0;
  }
};

}  // namespace

TEST_GROUP(Stm32Board){};

TEST(Stm32Board, StartSetsEveryPinAsThePinMapSaysWithTheDriversOn) {
  BlackPill pill;
  for (int i = 0; i < static_cast<int>(Pin::kCount); ++i) {
    const stm32::PinMap& p = stm32::pin_map(static_cast<Pin>(i));
    UNSIGNED_LONGS_EQUAL(p.output ? 1 : 0, pill.chip.mode(p.port, p.number));
    UNSIGNED_LONGS_EQUAL(p.pull, pill.chip.pull(p.port, p.number));
    if (p.output) CHECK_EQUAL(p.active_low, pill.chip.output_high(p.port, p.number));  // de-asserted
  }
  UNSIGNED_LONGS_EQUAL(1, pill.chip.mode(stm32::kDriverEnablePort, stm32::kDriverEnablePin));
  CHECK_TRUE(pill.drivers_enabled());
}

TEST(Stm32Board, ASwitchWithACutWireReadsAssertedAndAClosedOneDoesNot) {
  BlackPill pill;
  CHECK_TRUE(pill.board.read_pin(Pin::kLimitXMin));  // nothing drives it: the pull-up
  pill.drive(Pin::kLimitXMin, false);                 // closed to ground
  CHECK_FALSE(pill.board.read_pin(Pin::kLimitXMin));
  pill.drive(Pin::kEstop, true);
  CHECK_TRUE(pill.board.read_pin(Pin::kEstop));
}

TEST(Stm32Board, StepPulseIsHeldHighTwoMicroseconds) {
  BlackPill pill;
  pill.board.write_pin(Pin::kStepX, true);
  pill.board.write_pin(Pin::kStepX, false);
  const stm32::PinMap& p = stm32::pin_map(Pin::kStepX);
  std::vector<FakeStm32::PinChange> step;
  for (const auto& c : pill.outputs) {
    if (c.port == p.port && c.pin == p.number) step.push_back(c);
  }
  LONGS_EQUAL(2, step.size());
  CHECK_TRUE(step[1].cycle - step[0].cycle >= 2 * kCyclesPerUs);
  CHECK_TRUE(step[1].cycle - step[0].cycle <= 2 * kCyclesPerUs + 8);
}

TEST(Stm32Board, StepTimerChainsIntervalsWithoutDrift) {
  BlackPill pill;
  // 10,417 ns is 1000.032 ticks of 96 MHz: the fraction is carried, not dropped.
  Calls calls{{}, &pill.chip, 10417, 1000};
  pill.board.start_step_timer(calls.interval_ns, Calls::tick, &calls);
  pill.chip.run_for(12 * kCyclesPerUs * 1000);
  LONGS_EQUAL(1000, calls.at.size());
  for (size_t k = 1; k < calls.at.size(); ++k) {
    const uint64_t interval = calls.at[k] - calls.at[k - 1];
    CHECK_TRUE(interval == 1000 || interval == 1001);
  }
  const double exact = 999 * 10417 * 0.096;
  DOUBLES_EQUAL(exact, static_cast<double>(calls.at.back() - calls.at.front()), 1.0);
  // Stopped by the handler's 0: no call after it.
  pill.chip.run_for(100 * kCyclesPerUs);
  LONGS_EQUAL(1000, calls.at.size());
}

TEST(Stm32Board, AStepLateBehindMaskedInterruptsStretchesTheMoveInsteadOfBursting) {
  BlackPill pill;
  Calls calls{{}, &pill.chip, 10000, 40};
  pill.board.start_step_timer(calls.interval_ns, Calls::tick, &calls);
  pill.chip.run_for(55 * kCyclesPerUs);
  const size_t before = calls.at.size();
  {
    stm32::CriticalSection masked;  // 50 us with interrupts off: five steps fall due
    pill.chip.run_for(50 * kCyclesPerUs);
  }
  pill.chip.run_for(400 * kCyclesPerUs);
  LONGS_EQUAL(40, calls.at.size());
  CHECK_TRUE(calls.at[before] - calls.at[before - 1] >= 50 * kCyclesPerUs);  // the late one
  for (size_t k = before + 1; k < calls.at.size(); ++k) {
    CHECK_TRUE(calls.at[k] - calls.at[k - 1] >= 10 * kCyclesPerUs - 1);  // and no burst after it
  }
}

TEST(Stm32Board, EdgeInterruptRunsItsHandlerOncePerRisingEdge) {
  BlackPill pill;
  int edges = 0;
  pill.board.on_rising_edge(Pin::kGaugeClock, [](void* n) { ++*static_cast<int*>(n); }, &edges);
  pill.drive(Pin::kGaugeClock, false);
  pill.drive(Pin::kGaugeClock, true);
  pill.drive(Pin::kGaugeClock, false);
  LONGS_EQUAL(1, edges);
  pill.drive(Pin::kGaugeClock, true);
  LONGS_EQUAL(2, edges);
}

// now_us() in the main thread and in a gauge-clock interrupt that outranks the clock's own
// interrupt, with the edge moved across every cycle of a window that holds TIM5's wrap: every
// reading, in the order they were taken, is no earlier than the one before.
TEST(Stm32Board, ClockStaysMonotonicAcrossItsWrapWhereverAnInterruptFalls) {
  for (uint64_t offset = 0; offset < 8 * kCyclesPerUs; offset += 3) {
    BlackPill pill;
    // The largest reading finished so far: a reading taken after it may not be smaller. An
    // interrupt's reading lands in the middle of the main thread's, whose own value may still be
    // the smaller one: it was taken before.
    struct Seen {
      stm32::Stm32Board* board;
      uint64_t latest = 0;
      size_t readings = 0;
      bool backwards = false;
      void take() {
        const uint64_t floor = latest;
        const uint64_t us = board->now_us();
        backwards = backwards || us < floor;
        latest = std::max(latest, us);
        ++readings;
      }
    } seen{&pill.board};
    pill.board.on_rising_edge(Pin::kGaugeClock, [](void* s) { static_cast<Seen*>(s)->take(); }, &seen);
    pill.drive(Pin::kGaugeClock, false);
    pill.chip.set_counter(stm32::kTim5, 0xFFFFFFFFu - 3);
    const uint64_t start = pill.chip.cycles();
    pill.chip.at(start + offset, [&pill] { pill.drive(Pin::kGaugeClock, true); });
    while (pill.chip.cycles() < start + 10 * kCyclesPerUs) seen.take();
    CHECK_TRUE(seen.latest >= (uint64_t{1} << 32));
    CHECK_TRUE(seen.readings > 10);
    if (seen.backwards) FAIL("now_us() went back in time");
  }
}

TEST(Stm32Board, ResetCauseIsTheMostTellingFlagAndTheFlagsAreCleared) {
  {
    BlackPill pill(stm32::kCsrIwdgRstf | stm32::kCsrPinRstf);
    CHECK(pill.board.reset_cause() == dg::hal::ResetCause::kWatchdog);
    UNSIGNED_LONGS_EQUAL(0, pill.chip.read(stm32::kRccCsr) & 0xFF000000u);
  }
  {
    BlackPill pill(stm32::kCsrPorRstf | stm32::kCsrPinRstf | stm32::kCsrBorRstf);
    CHECK(pill.board.reset_cause() == dg::hal::ResetCause::kPowerOn);
  }
}

TEST(Stm32Board, WatchdogResetsABoardThatStopsKickingItAndOnlyThen) {
  BlackPill pill;
  pill.board.watchdog_start(100);
  for (int k = 0; k < 8; ++k) {
    pill.chip.run_for(25000 * kCyclesPerUs);  // kicked every 25 ms for 200 ms
    pill.board.watchdog_kick();
  }
  CHECK_FALSE(pill.chip.watchdog_fired());
  pill.chip.run_for(95000 * kCyclesPerUs);
  CHECK_FALSE(pill.chip.watchdog_fired());
  pill.chip.run_for(15000 * kCyclesPerUs);  // 110 ms without a kick: the nominal LSI's 102 ms passed
  CHECK_TRUE(pill.chip.watchdog_fired());
}

TEST(Stm32Board, WaitSleepsUntilItsDeadline) {
  BlackPill pill;
  const uint64_t from = pill.board.now_us();
  uint64_t now = from;
  while (now < from + 5000) {
    pill.board.wait(from + 5000);
    now = pill.board.now_us();
  }
  CHECK_TRUE(now - from <= 5001);
}

TEST_GROUP(Stm32BoardStepping){};

TEST(Stm32BoardStepping, AMoveTakesEveryStepOnThePinsWithinTheRateLimit) {
  BlackPill pill;
  dg::MotionConfig config;
  dg::StepGenerator steps(pill.board, config);
  pill.drive(Pin::kEstop, false);  // closed: not pressed
  pill.drive(Pin::kLimitXMin, false);
  pill.drive(Pin::kLimitYMin, false);
  LONGS_EQUAL(static_cast<int>(dg::Status::kOk), static_cast<int>(steps.move_to(800, 300, 0)));
  while (steps.busy() && pill.chip.cycles() < 2 * FakeStm32::kCoreHz) pill.chip.run_for(1000 * kCyclesPerUs);
  CHECK_FALSE(steps.busy());
  LONGS_EQUAL(800, steps.x_steps());
  LONGS_EQUAL(300, steps.y_steps());
  const std::vector<uint64_t> x = pill.rises(Pin::kStepX), y = pill.rises(Pin::kStepY);
  LONGS_EQUAL(800, x.size());
  LONGS_EQUAL(300, y.size());
  CHECK_TRUE(pill.chip.output_high(stm32::pin_map(Pin::kDirX).port, stm32::pin_map(Pin::kDirX).number));
  const uint64_t fastest = FakeStm32::kCoreHz / config.max_rate_steps_s;
  for (size_t k = 1; k < x.size(); ++k) CHECK_TRUE(x[k] - x[k - 1] >= fastest - fastest / 50);
}

// Pressed mid-move at cruise: the edge interrupt confirms it after 20 us and cuts the drivers'
// enable line; no STEP pulse leaves after the cut. Target: within 50 us of the pin.
TEST(Stm32BoardStepping, EstopEdgeCutsTheDriversWithinFiftyMicroseconds) {
  BlackPill pill;
  dg::MotionConfig config;
  dg::StepGenerator steps(pill.board, config);
  steps.attach_estop();
  pill.drive(Pin::kEstop, false);
  pill.drive(Pin::kLimitXMin, false);
  pill.drive(Pin::kLimitYMin, false);
  LONGS_EQUAL(static_cast<int>(dg::Status::kOk), static_cast<int>(steps.move_to(8000, 0, 0)));
  pill.chip.run_for(300000 * kCyclesPerUs);  // 0.3 s: at cruise
  CHECK_TRUE(steps.busy());
  const uint64_t pressed = pill.chip.cycles() + 17;  // off the step interrupt's rhythm
  pill.chip.at(pressed, [&pill] { pill.drive(Pin::kEstop, true); });
  pill.chip.run_for(5000 * kCyclesPerUs);
  const uint64_t cut = pill.drivers_cut_at(pressed);
  CHECK_FALSE(pill.drivers_enabled());
  CHECK_TRUE(cut > pressed);
  CHECK_TRUE(cut - pressed <= 50 * kCyclesPerUs);
  CHECK_TRUE(cut - pressed >= dg::StepGenerator::kConfirmNs * kCyclesPerUs / 1000);  // confirmed, not on the first read
  CHECK_FALSE(steps.busy());
  CHECK(steps.trip() == dg::Trip::kEstop);
  for (uint64_t at : pill.rises(Pin::kStepX)) CHECK_TRUE(at < cut);
}

namespace {

// The table under the board's pins: STEP rising edges move each axis by one step in the direction
// DIR gives, and each min switch (normally closed to ground, so open and high when pressed) opens
// where its axis is at or below the switch. `wired` false: the switch's wire is cut.
struct TableOnPins {
  BlackPill& pill;
  int32_t x_steps, y_steps;  // where the table is, from the switches' trip points
  bool wired_x = true, wired_y = true;

  TableOnPins(BlackPill& p, int32_t x, int32_t y) : pill(p), x_steps(x), y_steps(y) {
    pill.watch = [this](const FakeStm32::PinChange& c) { on_output(c); };
    switches();
  }
  void on_output(const FakeStm32::PinChange& c) {
    const stm32::PinMap &step_x = stm32::pin_map(Pin::kStepX), &step_y = stm32::pin_map(Pin::kStepY);
    if (!c.high) return;
    if (!pill.drivers_enabled()) return;  // no current: a step does nothing
    if (c.port == step_x.port && c.pin == step_x.number) x_steps += level(Pin::kDirX) ? 1 : -1;
    if (c.port == step_y.port && c.pin == step_y.number) y_steps += level(Pin::kDirY) ? 1 : -1;
    switches();
  }
  bool level(Pin pin) const { return pill.chip.output_high(stm32::pin_map(pin).port, stm32::pin_map(pin).number); }
  void switches() {
    auto set = [this](Pin pin, bool wired, bool pressed) {
      const stm32::PinMap& p = stm32::pin_map(pin);
      if (wired) pill.chip.drive(p.port, p.number, pressed);
      else pill.chip.release(p.port, p.number);
    };
    set(Pin::kLimitXMin, wired_x, x_steps <= 0);
    set(Pin::kLimitYMin, wired_y, y_steps <= 0);
  }
};

// Runs homing to its end (or 60 s of the chip's time), polled every millisecond as the device's
// main loop would.
void home(BlackPill& pill, dg::Homing& homing) {
  homing.start();
  while (homing.active() && pill.chip.cycles() < 60ull * FakeStm32::kCoreHz) {
    pill.chip.run_for(1000 * kCyclesPerUs);
    homing.poll();
  }
}

}  // namespace

TEST_GROUP(Stm32BoardMachine){};

TEST(Stm32BoardMachine, HomingFindsBothSwitchesAndPullsOffThem) {
  BlackPill pill;
  pill.drive(Pin::kEstop, false);
  TableOnPins table(pill, 3000, 2000);  // 7.5 and 5 mm off the switches
  dg::MotionConfig config;
  dg::StepGenerator steps(pill.board, config);
  dg::Homing homing(steps);
  home(pill, homing);
  CHECK_TRUE(homing.done());
  // At rest a pull-off from each switch's trip point (the table's 0), where the generator's
  // count says it is: the trip point is the machine's home_switch_steps.
  LONGS_EQUAL(1 + config.home_pull_off_steps, table.x_steps);
  LONGS_EQUAL(1 + config.home_pull_off_steps, table.y_steps);
  LONGS_EQUAL(table.x_steps + config.home_switch_steps, steps.x_steps());
  LONGS_EQUAL(table.y_steps + config.home_switch_steps, steps.y_steps());
  CHECK_FALSE(pill.board.read_pin(Pin::kLimitXMin));
}

TEST(Stm32BoardMachine, HomingWithACutSwitchWireFailsWithAReason) {
  BlackPill pill;
  pill.drive(Pin::kEstop, false);
  TableOnPins table(pill, 3000, 2000);
  table.wired_x = false;
  table.switches();
  dg::MotionConfig config;
  dg::StepGenerator steps(pill.board, config);
  dg::Homing homing(steps);
  home(pill, homing);
  CHECK_TRUE(homing.failed());
  STRCMP_CONTAINS("unwired or cut", homing.failure());
  LONGS_EQUAL(0, table.y_steps - 2000);  // x failed first: y never moved
}

// A Digimatic gauge clocks its 52-bit frame out on CK and DATA after REQ; the reader samples DATA
// in the EXTI2 interrupt of each CK edge.
TEST(Stm32BoardMachine, GaugeFrameIsReadThroughTheClockEdgeInterrupt) {
  BlackPill pill;
  dg::sim::GaugeConfig gauge_config;
  dg::sim::DigimaticGauge gauge(gauge_config, 1);
  auto ns = [&pill] { return pill.chip.cycles() * 1000 / kCyclesPerUs / 1000; };
  const double height_mm = 12.345;
  std::function<void()> next_edge = [&] {
    if (gauge.next_event_ns() == UINT64_MAX) return;
    pill.chip.at(gauge.next_event_ns() * kCyclesPerUs / 1000, [&] {
      gauge.advance();
      pill.drive(Pin::kGaugeData, gauge.data());
      pill.drive(Pin::kGaugeClock, gauge.clock());
      next_edge();
    });
  };
  pill.watch = [&](const FakeStm32::PinChange& c) {
    const stm32::PinMap& req = stm32::pin_map(Pin::kGaugeReq);
    if (c.port != req.port || c.pin != req.number) return;
    gauge.set_request(c.high, ns(), height_mm);
    next_edge();
  };
  pill.drive(Pin::kGaugeClock, gauge.clock());
  pill.drive(Pin::kGaugeData, gauge.data());
  dg::DigimaticReader reader(pill.board, dg::DigimaticTiming{});
  reader.attach();
  LONGS_EQUAL(static_cast<int>(dg::Status::kOk), static_cast<int>(reader.start()));
  dg::DigimaticReader::State state = reader.poll();
  while (state == dg::DigimaticReader::State::kReading && pill.chip.cycles() < FakeStm32::kCoreHz) {
    pill.chip.run_for(100 * kCyclesPerUs);
    state = reader.poll();
  }
  CHECK(state == dg::DigimaticReader::State::kDone);
  LONGS_EQUAL(52, reader.bits_received());
  LONGS_EQUAL(12345000, reader.value_nm());
}

// A probing move at 1 mm/s (steps 2.5 ms apart). The stylus meets a face between two steps and
// stays deflected: the EXTI15 edge latches the step count at that moment, the next step confirms
// and the move brakes within its overtravel, as with the read before each step alone. Contacts
// that open for 100 us between two steps and close again are a bounce, not a touch, either way.
TEST(Stm32BoardMachine, ATouchIsLatchedByTheProbesEdgeAndABounceIsNot) {
  for (int run = 0; run < 4; ++run) {
    const bool edge = run % 2 == 0, bounce = run >= 2;
    BlackPill pill;
    pill.drive(Pin::kEstop, false);
    pill.drive(Pin::kLimitXMin, false);
    pill.drive(Pin::kLimitYMin, false);
    pill.drive(Pin::kTouchProbe, false);  // contacts closed: at rest
    dg::StepGenerator steps(pill.board, dg::MotionConfig{});
    if (edge) steps.attach_probe();
    steps.set_position(4000, 0);
    LONGS_EQUAL(static_cast<int>(dg::Status::kOk), static_cast<int>(steps.probe_to(12000, 0, 400, 200)));
    while (pill.rises(Pin::kStepX).size() < 50) pill.chip.run_for(100 * kCyclesPerUs);
    const uint64_t touch = pill.rises(Pin::kStepX).back() + 300 * kCyclesPerUs;
    pill.chip.at(touch, [&pill] { pill.drive(Pin::kTouchProbe, true); });
    if (bounce) pill.chip.at(touch + 100 * kCyclesPerUs, [&pill] { pill.drive(Pin::kTouchProbe, false); });
    pill.chip.run_for(touch - pill.chip.cycles() + kCyclesPerUs);
    const int32_t at_touch = 4000 + static_cast<int32_t>(pill.rises(Pin::kStepX).size());
    while (steps.busy() && pill.chip.cycles() < 60ull * FakeStm32::kCoreHz) pill.chip.run_for(1000 * kCyclesPerUs);
    CHECK_FALSE(steps.busy());
    if (bounce) {
      CHECK_FALSE(steps.touched());
      LONGS_EQUAL(12000, steps.x_steps());
    } else {
      CHECK_TRUE(steps.touched());
      LONGS_EQUAL(at_touch, steps.touch_x_steps());
      CHECK_TRUE(steps.x_steps() > at_touch);
      CHECK_TRUE(steps.x_steps() <= at_touch + 200);
    }
  }
}

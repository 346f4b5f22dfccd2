// Device commands end to end through the simulated device: status, a jog and its soft limit, a
// command the firmware does not have yet, and where a jog leaves the table.
#include <CppUTest/TestHarness.h>

#include <chrono>

#include <string>
#include <thread>

#include "host/device/repeatability.h"
#include "host/device/request.h"
#include "host/transport/transport.h"

namespace {

digitizer_Envelope command(digitizer_CommandKind kind, int32_t dx_nm = 0) {
  digitizer_Envelope m = digitizer_Envelope_init_zero;
  m.which_body = digitizer_Envelope_command_tag;
  m.body.command.kind = kind;
  m.body.command.dx_nm = dx_nm;
  return m;
}

std::string refusal(dg::host::Session& session, digitizer_Envelope message) {
  try {
    dg::host::request(session, message, 5000);
  } catch (const dg::host::DeviceError& e) {
    return e.what();
  }
  return "";
}

// The device's status, asked for in a session.
digitizer_Status status_of(dg::host::Session& session) {
  digitizer_Envelope ask = command(digitizer_CommandKind_CMD_STATUS);
  const digitizer_Envelope reply = dg::host::request(session, ask, 5000);
  LONGS_EQUAL(digitizer_Envelope_status_tag, reply.which_body);
  return reply.body.status;
}

}  // namespace

TEST_GROUP(SimCommands){};

TEST(SimCommands, StatusJogAndRefusalsCarryTheDevicesWords) {
  auto transport = dg::host::open_transport("sim:part=flat,start_x_mm=12.5,start_y_mm=7.5");
  dg::host::Session session(*transport);
  session.hello(5000);
  LONGS_EQUAL(digitizer_DeviceState_STATE_IDLE, status_of(session).state);
  // Refusals first: a jog that is still moving would make any later command "busy".
  STRCMP_CONTAINS("soft limit", refusal(session, command(digitizer_CommandKind_CMD_JOG, 900000000)).c_str());
  // Homing: the table starts 12.5 mm, 7.5 mm from its switches (start_x_mm, start_y_mm) and
  // ends 1 mm off both, homed.
  auto wait_idle = [&session] {
    // Homing takes some 20 s of table time; the simulator needs a while of real time for it.
    digitizer_Envelope after = digitizer_Envelope_init_zero;
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (std::chrono::steady_clock::now() < give_up) {
      digitizer_Envelope ask = command(digitizer_CommandKind_CMD_STATUS);
      after = dg::host::request(session, ask, 5000);
      if (after.body.status.state == digitizer_DeviceState_STATE_IDLE) break;
    }
    return after;
  };
  digitizer_Envelope home = command(digitizer_CommandKind_CMD_HOME);
  LONGS_EQUAL(digitizer_Envelope_accepted_tag, dg::host::request(session, home, 5000).which_body);
  digitizer_Envelope after = wait_idle();
  CHECK(after.body.status.homed);
  LONGS_EQUAL(1000000, after.body.status.x_nm);
  LONGS_EQUAL(1000000, after.body.status.y_nm);
  digitizer_Envelope jog = command(digitizer_CommandKind_CMD_JOG, 5000000);
  LONGS_EQUAL(digitizer_Envelope_accepted_tag, dg::host::request(session, jog, 5000).which_body);
  // The table ends where the jog sent it.
  after = wait_idle();
  LONGS_EQUAL(digitizer_DeviceState_STATE_IDLE, after.body.status.state);
  LONGS_EQUAL(6000000, after.body.status.x_nm);
}

TEST(SimCommands, TheTouchProbeFindsAFaceToTheStep) {
  auto transport = dg::host::open_transport("sim:part=flat,touch_x_mm=12.3456");
  dg::host::Session session(*transport);
  session.hello(5000, digitizer_Capability_CAP_TOUCH_PROBE);
  digitizer_Envelope touch = command(digitizer_CommandKind_CMD_TOUCH, 30000000);
  touch.body.command.feed_um_s = 4000;
  const uint32_t id = dg::host::request(session, touch, 5000).id;
  digitizer_Envelope reply = digitizer_Envelope_init_zero;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < give_up) {
    if (session.receive(&reply, 500) && reply.id == id && reply.which_body == digitizer_Envelope_touch_result_tag) break;
  }
  LONGS_EQUAL(digitizer_Envelope_touch_result_tag, reply.which_body);
  CHECK(reply.body.touch_result.touched);
  // The simulator puts the face on the nearest step (4938 x 2.5 um = 12.345 mm); the latch is
  // that step exactly.
  LONGS_EQUAL(12345000, reply.body.touch_result.x_nm);
  CHECK(reply.body.touch_result.stop_x_nm >= reply.body.touch_result.x_nm);
  CHECK(reply.body.touch_result.stop_x_nm <= reply.body.touch_result.x_nm + 1000000);
}

// The repeatability a scan stores for its points' uncertainty, measured where the scan starts: the
// simulated gauge's true noise (5 um, Gaussian) is the oracle. 64 readings estimate a standard
// deviation to about 9 %; the band is three times that.
TEST(SimCommands, RepeatabilityAtTheFirstPointFindsTheGaugesTrueNoise) {
  auto transport = dg::host::open_transport("sim:part=flat,noise_um=5,seed=11");
  dg::host::Session session(*transport);
  const digitizer_Hello hello = session.hello(5000);
  dg::host::move_table_to(session, 10000000, 8000000, hello.axis_resolution_nm, 10000, 60000);
  const digitizer_Repeatability r = dg::host::measure_repeatability(session, 64);
  LONGS_EQUAL(64, r.count);
  LONGS_EQUAL(10000000, r.x_nm);
  LONGS_EQUAL(8000000, r.y_nm);
  CHECK_TRUE(r.stddev_nm > 3650 && r.stddev_nm < 6350);
  CHECK_TRUE(r.min_nm < r.mean_nm && r.mean_nm < r.max_nm);
}

TEST(SimCommands, AMoveToAPointOffTheTableIsRefusedWithTheDevicesReason) {
  auto transport = dg::host::open_transport("sim:part=flat");
  dg::host::Session session(*transport);
  const digitizer_Hello hello = session.hello(5000);
  try {
    dg::host::move_table_to(session, 900000000, 0, hello.axis_resolution_nm, 10000, 60000);
    FAIL("a move off the table was not refused");
  } catch (const dg::host::DeviceError& e) {
    STRCMP_CONTAINS("soft limit", e.what());
  }
}

// The simulator's firmware hangs 1 ms after it starts; its watchdog resets it, the simulator starts
// the firmware again as the MCU would, and a host that connects then is told why it started.
TEST(SimCommands, AFirmwareTheWatchdogResetSaysSoInItsStatus) {
  auto transport = dg::host::open_transport("sim:watchdog_ms=200,hang_at_ms=1");
  // Virtual time stands still while the device waits for a host that talks; a silent one lets it
  // run (a quarter of the watchdog each 250 ms of real time), past the hang and the reset.
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  dg::host::Session session(*transport);
  session.hello(5000);
  const digitizer_Status status = status_of(session);
  LONGS_EQUAL(digitizer_ResetCause_RESET_WATCHDOG, status.reset_cause);
  LONGS_EQUAL(digitizer_DeviceState_STATE_IDLE, status.state);
}

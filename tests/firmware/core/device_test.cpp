// The device on the simulated board with an in-memory link and a scripted host: resuming (a host
// that vanishes mid-scan, comes back and states what it stored), a silent host, and the alarms of
// a hard limit and the e-stop.
#include "firmware/core/device.h"

#include <CppUTest/TestHarness.h>

#include <cstdlib>
#include <deque>
#include <new>
#include <vector>

#include "common/proto/messages.h"
#include "hw/sim/sim_board.h"
#include "tests/support/scan_request.h"

namespace {

// The wire as bytes in memory; a pulled cable loses what the device writes.
class MemoryLink final : public dg::hal::LinkPort {
 public:
  size_t write(const uint8_t* data, size_t size) override {
    // The device writes a frame at a time; a line that loses frames drops every drop_every-th.
    const bool lost = drop_every > 0 && ++writes % drop_every == 0;
    if (connected && !lost) to_host.insert(to_host.end(), data, data + size);
    return size;
  }
  size_t read(uint8_t* data, size_t capacity) override {
    size_t n = 0;
    while (n < capacity && !to_device.empty()) {
      data[n++] = to_device.front();
      to_device.pop_front();
    }
    return n;
  }
  bool wait_readable(int) override { return !to_device.empty(); }
  bool closed() const override { return false; }

  bool connected = true;
  unsigned drop_every = 0;  // 0: none lost
  unsigned writes = 0;
  std::deque<uint8_t> to_device;
  std::vector<uint8_t> to_host;
};

// A host: the common reliable link, a store of points that keeps each once, in order.
struct ScriptedHost {
  explicit ScriptedHost(MemoryLink& wire) : wire(wire) {}

  void send(digitizer_Envelope message, bool sync = false, uint16_t session = 1) {
    uint8_t payload[dg::kFrameMaxPayload];
    size_t size = 0;
    CHECK(dg::encode_envelope(message, payload, sizeof(payload), &size) == dg::Status::kOk);
    if (sync) {
      link.send_sync(payload, size, now_us, session);
    } else {
      CHECK(link.send(payload, size, now_us) == dg::Status::kOk);
    }
  }
  // Reads what the device wrote, stores and acknowledges points, writes due frames.
  void exchange() {
    size_t offset = 0;
    while (offset < wire.to_host.size()) {
      size_t used = 0;
      const dg::Status status = decoder.feed(wire.to_host.data() + offset, wire.to_host.size() - offset, &used);
      offset += used;
      if (status != dg::Status::kOk) continue;
      if (!link.receive(decoder.header(), now_us)) continue;
      digitizer_Envelope message;
      CHECK(dg::decode_envelope(decoder.payload(), decoder.payload_size(), &message) == dg::Status::kOk);
      handle(message);
    }
    wire.to_host.clear();
    uint8_t frame[dg::kFrameMaxWire];
    size_t size = 0;
    while (link.next_frame(now_us, frame, sizeof(frame), &size)) wire.to_device.insert(wire.to_device.end(), frame, frame + size);
  }
  void handle(const digitizer_Envelope& message) {
    received.push_back(message);
    if (message.which_body == digitizer_Envelope_scan_done_tag) done = message.body.scan_done;
    if (message.which_body != digitizer_Envelope_points_tag) return;
    dg::PointSample batch[dg::kMaxPointsPerBatch];
    size_t count = 0;
    CHECK(dg::point_batch_expand(message.body.points, batch, &count) == dg::Status::kOk);
    for (size_t i = 0; i < count; ++i) {
      if (!stored.empty() && batch[i].seq <= stored.back().seq) continue;  // resent: have it
      if (!stored.empty()) LONGS_EQUAL(stored.back().seq + 1, batch[i].seq);  // never a gap
      stored.push_back(batch[i]);
    }
    if (!acking || stored.empty()) return;
    digitizer_Envelope ack = digitizer_Envelope_init_zero;
    ack.which_body = digitizer_Envelope_point_ack_tag;
    ack.body.point_ack.seq = stored.back().seq;
    send(ack);
  }
  const digitizer_Envelope* last(pb_size_t tag) const {
    for (auto m = received.rbegin(); m != received.rend(); ++m) {
      if (m->which_body == tag) return &*m;
    }
    return nullptr;
  }

  MemoryLink& wire;
  dg::ReliableLink<8> link{50000};
  dg::FrameDecoder decoder;
  uint64_t now_us = 0;
  bool acking = true;
  std::vector<dg::PointSample> stored;
  std::vector<digitizer_Envelope> received;
  digitizer_ScanDone done = digitizer_ScanDone_init_zero;
};

dg::DeviceConfig device_config(dg::HostSilence on_silence) {
  dg::DeviceConfig c;
  c.motion.nm_per_step = 2500;
  c.capabilities = digitizer_Capability_CAP_DIGIMATIC | digitizer_Capability_CAP_RESUME;
  c.gauge.first_clock_timeout_us = 200000;
  c.host_silence_us = 2000000;
  c.on_host_silence = on_silence;
  return c;
}

struct Bench {
  explicit Bench(dg::HostSilence on_silence = dg::HostSilence::kPause, const dg::sim::SimConfig& sim = sim_config(),
                 bool require_homing = false, uint32_t watchdog_ms = 0)
      : board(sim, &wire), config(with(device_config(on_silence), require_homing, watchdog_ms)), device(board, config), host(wire) {
    device.begin();
  }
  static dg::DeviceConfig with(dg::DeviceConfig c, bool require_homing, uint32_t watchdog_ms) {
    c.require_homing = require_homing;
    c.watchdog_ms = watchdog_ms;
    return c;
  }
  // The board reset: the firmware starts again from scratch on the same table, as the MCU would.
  void restart_firmware() {
    device.~Device();
    new (&device) dg::Device(board, config);
    device.begin();
  }
  void command(digitizer_CommandKind kind, uint32_t id) {
    digitizer_Envelope m = digitizer_Envelope_init_zero;
    m.id = id;
    m.which_body = digitizer_Envelope_command_tag;
    m.body.command.kind = kind;
    host.send(m);
  }
  // CMD_SET_CALIBRATION with a summary of `version` (0: none, which the device refuses).
  void set_calibration(uint32_t id, uint32_t version, uint64_t created_unix_s = 0, uint32_t file_crc32 = 0, uint32_t parts = 0) {
    digitizer_Envelope m = digitizer_Envelope_init_zero;
    m.id = id;
    m.which_body = digitizer_Envelope_command_tag;
    m.body.command.kind = digitizer_CommandKind_CMD_SET_CALIBRATION;
    m.body.command.has_calibration = true;
    m.body.command.calibration.version = version;
    m.body.command.calibration.created_unix_s = created_unix_s;
    m.body.command.calibration.file_crc32 = file_crc32;
    m.body.command.calibration.parts = parts;
    host.send(m);
  }
  const digitizer_Envelope* fault_for(uint32_t id) const {
    for (auto m = host.received.rbegin(); m != host.received.rend(); ++m) {
      if (m->which_body == digitizer_Envelope_fault_tag && m->body.fault.request_id == id) return &*m;
    }
    return nullptr;
  }
  static dg::sim::SimConfig sim_config() {
    dg::sim::SimConfig c;
    c.part.kind = dg::sim::PartKind::kDome;
    return c;
  }
  // Runs device and host for `us` of device time, or until nothing more can happen.
  void run_for(uint64_t us) {
    const uint64_t until = board.now_us() + us;
    int idle_rounds = 0;
    while (board.now_us() < until && idle_rounds < 1000) {
      const uint64_t before = board.now_us();
      device.poll();
      if (wire.connected) {
        host.now_us = board.now_us();
        host.exchange();
      }
      const uint64_t deadline = device.next_deadline_us();
      if (!board.wait(deadline < until ? deadline : until) && wire.to_device.empty()) return;
      idle_rounds = board.now_us() == before ? idle_rounds + 1 : 0;
    }
  }
  void run_until_done(uint64_t limit_us) {
    const uint64_t until = board.now_us() + limit_us;
    while (board.now_us() < until && host.last(digitizer_Envelope_scan_done_tag) == nullptr) run_for(100000);
  }
  void hello(uint16_t session, uint32_t required = 0) {
    digitizer_Envelope m = digitizer_Envelope_init_zero;
    m.id = 100 + session;
    m.which_body = digitizer_Envelope_host_hello_tag;
    m.body.host_hello.protocol_version = digitizer_ProtocolVersion_PROTOCOL_VERSION;
    m.body.host_hello.min_protocol_version = digitizer_ProtocolVersion_PROTOCOL_VERSION;
    m.body.host_hello.required_capabilities = required;
    host.send(m, true, session);
  }
  void start_scan(uint32_t id = 1) {
    digitizer_Envelope m = digitizer_Envelope_init_zero;
    m.id = id;
    m.which_body = digitizer_Envelope_scan_request_tag;
    m.body.scan_request = request;
    host.send(m);
  }
  void resume(uint32_t scan_id, uint32_t next_seq) {
    digitizer_Envelope m = digitizer_Envelope_init_zero;
    m.id = 2;
    m.which_body = digitizer_Envelope_resume_scan_tag;
    m.body.resume_scan.scan_id = scan_id;
    m.body.resume_scan.next_seq = next_seq;
    host.send(m);
  }
  // Starts the scan, lets it run for `us`, then pulls the cable and lets `silent_us` pass.
  void scan_then_lose_host(uint64_t us, uint64_t silent_us) {
    hello(1);
    start_scan();
    run_for(us);
    wire.connected = false;
    run_for(silent_us);
  }
  // A host process that died: its link state is gone with it; the cable is plugged back.
  void new_host() {
    host.link.reset();
    host.decoder.reset();
    wire.to_device.clear();
    wire.to_host.clear();
    wire.connected = true;
  }

  // 41 x 11 points at 1 mm: longer than the 128-point ring.
  digitizer_ScanRequest request = dg::test::grid_request(77, 0, 40000000, 10000000, 1000000, digitizer_ScanPattern_PATTERN_SERPENTINE);
  MemoryLink wire;
  dg::sim::SimBoard board;
  dg::DeviceConfig config;
  dg::Device device;
  ScriptedHost host;
};

void check_every_point_once(const std::vector<dg::PointSample>& stored, size_t expected) {
  LONGS_EQUAL(expected, stored.size());
  for (size_t i = 0; i < stored.size(); ++i) LONGS_EQUAL(stored.front().seq + i, stored[i].seq);
}

// The most points one batch among received[from..] held.
size_t largest_batch(const std::vector<digitizer_Envelope>& received, size_t from) {
  size_t largest = 0;
  for (size_t i = from; i < received.size(); ++i) {
    const digitizer_Envelope& m = received[i];
    if (m.which_body == digitizer_Envelope_points_tag && m.body.points.dx_nm_count > largest) largest = m.body.points.dx_nm_count;
  }
  return largest;
}

}  // namespace

TEST_GROUP(DeviceWatchdog){};

// The main loop kicks the watchdog and never sleeps past a quarter of it, through a whole scan
// with its waits for the gauge, the host and the motors, and a 300 ms settling wait at every
// point that it would otherwise sleep through: a 100 ms watchdog never fires.
TEST(DeviceWatchdog, ALoopThatKeepsRunningIsNeverResetThroughAWholeScan) {
  Bench bench(dg::HostSilence::kPause, Bench::sim_config(), false, 100);
  bench.request.settle_ms = 300;
  bench.hello(1);
  bench.start_scan();
  // The simulated link wakes the loop every millisecond anyway; what a board whose link sleeps
  // needs is that the loop never asks to sleep longer than 25 ms.
  uint64_t longest_sleep_us = 0;
  for (int round = 0; round < 10000000 && bench.host.last(digitizer_Envelope_scan_done_tag) == nullptr; ++round) {
    bench.device.poll();
    bench.host.now_us = bench.board.now_us();
    bench.host.exchange();
    const uint64_t deadline = bench.device.next_deadline_us();
    const uint64_t now = bench.board.now_us();
    if (deadline > now && deadline - now > longest_sleep_us) longest_sleep_us = deadline - now;
    if (!bench.board.wait(deadline)) break;
  }
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_COMPLETED, bench.host.done.reason);
  CHECK(longest_sleep_us <= 25000);
  CHECK(!bench.board.take_reset());
}

// A main loop that hangs mid-scan stops kicking: the watchdog resets the board within its
// timeout, the steps stop, and the restarted firmware's status says why it started.
TEST(DeviceWatchdog, AHungLoopIsResetWithinTheTimeoutAndStatusSaysWhy) {
  dg::sim::SimConfig sim = Bench::sim_config();
  sim.hang_at_ns = 3000000000ull;
  Bench bench(dg::HostSilence::kPause, sim, false, 500);
  bench.hello(1);
  bench.command(digitizer_CommandKind_CMD_STATUS, 2);
  bench.run_for(100000);
  const digitizer_Envelope* before = bench.host.last(digitizer_Envelope_status_tag);
  CHECK(before != nullptr);
  LONGS_EQUAL(digitizer_ResetCause_RESET_POWER_ON, before->body.status.reset_cause);
  bench.start_scan();
  bench.run_for(10000000);
  CHECK(bench.board.take_reset());
  CHECK(bench.board.now_ns() >= 3000000000ull + 500000000ull);
  CHECK(bench.board.now_ns() <= 3000000000ull + 750000000ull);  // the last kick came at most 125 ms before the hang
  const uint64_t steps = bench.board.step_count();
  bench.restart_firmware();
  bench.new_host();
  bench.hello(2);
  bench.command(digitizer_CommandKind_CMD_STATUS, 3);
  bench.run_for(1000000);
  LONGS_EQUAL(steps, bench.board.step_count());  // nothing moved after the reset
  const digitizer_Envelope* after = bench.host.last(digitizer_Envelope_status_tag);
  CHECK(after != nullptr && after != before);
  LONGS_EQUAL(digitizer_ResetCause_RESET_WATCHDOG, after->body.status.reset_cause);
  LONGS_EQUAL(digitizer_DeviceState_STATE_IDLE, after->body.status.state);
}

TEST_GROUP(DeviceResume){};

TEST(DeviceResume, PausesWhenTheHostFallsSilentAndResumesFromTheLastStoredPoint) {
  Bench bench;
  bench.hello(1);
  bench.start_scan();
  bench.run_for(3000000);
  const size_t before = bench.host.stored.size();
  CHECK(before > 0);
  CHECK(before < 41 * 11);
  // The cable is pulled: the device keeps scanning into its ring until the host's silence
  // pauses it.
  bench.wire.connected = false;
  bench.run_for(30000000);
  LONGS_EQUAL(digitizer_DeviceState_STATE_PAUSED, bench.device.state());
  CHECK(bench.device.ring_used() < 128);
  // A new host process: a fresh session, then the point it needs next.
  bench.new_host();
  bench.hello(2);
  bench.resume(77, bench.host.stored.back().seq + 1);
  bench.run_until_done(600000000);
  check_every_point_once(bench.host.stored, 41 * 11);
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_COMPLETED, bench.host.done.reason);
  LONGS_EQUAL(41 * 11, bench.host.done.points);
}

// A host that suspends the USB link (going to sleep) is not waited for: the scan pauses at once,
// not after the configured silence, and goes on from where it stopped when the host wakes and its
// link speaks again, every point once.
TEST(DeviceResume, PausesAtOnceWhenTheHostSuspendsTheLinkAndGoesOnAfterItsWakeUp) {
  Bench bench;
  bench.hello(1);
  bench.start_scan();
  bench.run_for(3000000);
  CHECK(bench.host.stored.size() > 0);
  bench.board.set_link_suspended(true);
  bench.wire.connected = false;
  bench.run_for(100000);
  LONGS_EQUAL(digitizer_DeviceState_STATE_PAUSED, bench.device.state());
  // Paused: the table stands still, however long the host sleeps.
  bench.run_for(1000000);
  const int64_t x = bench.board.table_x_steps(), y = bench.board.table_y_steps();
  bench.run_for(20000000);
  LONGS_EQUAL(x, bench.board.table_x_steps());
  LONGS_EQUAL(y, bench.board.table_y_steps());
  LONGS_EQUAL(digitizer_DeviceState_STATE_PAUSED, bench.device.state());
  bench.board.set_link_suspended(false);
  bench.wire.connected = true;
  bench.run_until_done(600000000);
  check_every_point_once(bench.host.stored, 41 * 11);
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_COMPLETED, bench.host.done.reason);
}

// A jog is the host's hand on the table: when the host suspends the link that hand is gone, and the
// table brakes to rest at once instead of running on to the jog's end.
TEST(DeviceResume, AJogStopsWhenTheHostSuspendsTheLink) {
  Bench bench;
  bench.hello(1);
  digitizer_Envelope jog = digitizer_Envelope_init_zero;
  jog.id = 20;
  jog.which_body = digitizer_Envelope_command_tag;
  jog.body.command.kind = digitizer_CommandKind_CMD_JOG;
  jog.body.command.dx_nm = 30000000;  // 30 mm at 1 mm/s: 30 s to its end
  jog.body.command.feed_um_s = 1000;
  bench.host.send(jog);
  bench.run_for(2000000);
  CHECK(bench.fault_for(20) == nullptr);
  LONGS_EQUAL(digitizer_DeviceState_STATE_JOGGING, bench.device.state());
  const int64_t start = bench.board.table_x_steps();
  CHECK(start > 0);
  bench.board.set_link_suspended(true);
  bench.run_for(1000000);
  const int64_t stopped = bench.board.table_x_steps();
  bench.run_for(20000000);
  LONGS_EQUAL(stopped, bench.board.table_x_steps());
  CHECK(stopped - start < 400);  // braked within a mm of where the suspend came, far from 30 mm
  LONGS_EQUAL(digitizer_DeviceState_STATE_IDLE, bench.device.state());
}

// Reference readings (the first point read again after every third line and after the last) are
// numbered among the points, so a resume must count them where each line starts: a scan resumed
// after a pulled cable still stores every point and every reading once, each reading ending its line.
TEST(DeviceResume, AScanWithReferenceReadingsResumesWithEveryReadingOnce) {
  Bench bench;
  bench.request.reference_every_lines = 3;
  bench.hello(1);
  bench.start_scan();
  // The cable goes once the first reading (after line 2) is stored, and the scan is not done.
  for (int s = 0; s < 120 && bench.host.stored.size() <= 41 * 3 + 1; ++s) bench.run_for(1000000);
  CHECK(bench.host.stored.size() > 41 * 3 + 1);
  CHECK(bench.host.stored.size() < 41 * 8);
  bench.wire.connected = false;
  bench.run_for(30000000);
  LONGS_EQUAL(digitizer_DeviceState_STATE_PAUSED, bench.device.state());
  bench.new_host();
  bench.hello(2);
  bench.resume(77, bench.host.stored.back().seq + 1);
  bench.run_until_done(600000000);
  // 11 lines: readings after lines 2, 5, 8 and 10.
  check_every_point_once(bench.host.stored, 41 * 11 + 4);
  LONGS_EQUAL(41 * 11 + 4, bench.host.done.points);
  size_t readings = 0;
  for (const dg::PointSample& p : bench.host.stored) {
    if ((p.flags & digitizer_PointFlag_POINT_REFERENCE) == 0) continue;
    ++readings;
    LONGS_EQUAL(bench.request.x.min_nm, p.x_nm);
    LONGS_EQUAL(bench.request.y.min_nm, p.y_nm);
    CHECK((p.flags & digitizer_PointFlag_POINT_LINE_END) != 0);
    CHECK(p.line == 2 || p.line == 5 || p.line == 8 || p.line == 10);
  }
  LONGS_EQUAL(4, readings);
  // Each line's LineDone counts its reading, before the cable was pulled and after the resume.
  for (const digitizer_Envelope& m : bench.host.received) {
    if (m.which_body != digitizer_Envelope_line_done_tag) continue;
    const uint32_t line = m.body.line_done.line;
    LONGS_EQUAL(line == 2 || line == 5 || line == 8 || line == 10 ? 42 : 41, m.body.line_done.points);
  }
}

TEST(DeviceResume, AFullRingStopsTheScanWhileNoPointIsAcknowledged) {
  Bench bench(dg::HostSilence::kContinue);
  bench.scan_then_lose_host(1000, 120000000);
  // Nothing lost, nothing dropped: the scan waits with a full ring.
  LONGS_EQUAL(128, bench.device.ring_used());
  LONGS_EQUAL(digitizer_DeviceState_STATE_SCANNING, bench.device.state());
  bench.new_host();
  bench.hello(2);
  bench.resume(77, 0);  // this host has none of the points
  bench.run_until_done(600000000);
  check_every_point_once(bench.host.stored, 41 * 11);
  LONGS_EQUAL(1, bench.host.stored.front().seq);
}

TEST(DeviceResume, AbortsOnASilentHostWhenConfiguredTo) {
  Bench bench(dg::HostSilence::kAbort);
  bench.scan_then_lose_host(3000000, 10000000);
  LONGS_EQUAL(digitizer_DeviceState_STATE_IDLE, bench.device.state());
  // The points measured before the abort are still there for the next host.
  bench.new_host();
  bench.hello(2);
  bench.resume(77, bench.host.stored.back().seq + 1);
  bench.run_until_done(60000000);
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_ABORTED, bench.host.done.reason);
  check_every_point_once(bench.host.stored, bench.host.done.points);
}

// The host died with the ring full; another host aborts. The scan ends at once (it used to wait
// for room in the ring for ever, scanning as far as `status` could tell), and every point it
// measured, the one waiting for the ring included, is still there for `--resume`.
TEST(DeviceResume, AnAbortEndsAScanWaitingOnAFullRingAndKeepsItsPoints) {
  Bench bench(dg::HostSilence::kContinue);
  bench.scan_then_lose_host(1000, 120000000);
  LONGS_EQUAL(128, bench.device.ring_used());
  bench.new_host();
  bench.hello(2);
  bench.command(digitizer_CommandKind_CMD_ABORT, 9);
  bench.host.acking = false;
  bench.run_for(1000000);
  LONGS_EQUAL(digitizer_DeviceState_STATE_IDLE, bench.device.state());
  // A new scan would push the held point out: refused until the aborted scan is fetched.
  bench.start_scan();
  bench.run_for(100000);
  const digitizer_Envelope* refused = bench.fault_for(1);
  CHECK(refused != nullptr);
  LONGS_EQUAL(digitizer_FaultCode_FAULT_BUSY, refused->body.fault.code);
  bench.host.acking = true;
  bench.host.stored.clear();
  bench.resume(77, 0);
  bench.run_until_done(60000000);
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_ABORTED, bench.host.done.reason);
  LONGS_EQUAL(129, bench.host.done.points);
  check_every_point_once(bench.host.stored, 129);
  LONGS_EQUAL(1, bench.host.stored.front().seq);
  // Fetched: the device takes a new scan.
  bench.host.received.clear();
  bench.start_scan();
  bench.run_for(2000000);
  CHECK(bench.fault_for(1) == nullptr);
  LONGS_EQUAL(digitizer_DeviceState_STATE_SCANNING, bench.device.state());
}

TEST(DeviceResume, SendsTheScanDoneAgainForAFinishedScan) {
  Bench bench;
  bench.hello(1);
  bench.start_scan();
  bench.run_until_done(600000000);
  const uint32_t last = bench.host.stored.back().seq;
  bench.new_host();
  bench.host.received.clear();
  bench.hello(2);
  bench.resume(77, last + 1);
  bench.run_for(2000000);
  const digitizer_Envelope* done = bench.host.last(digitizer_Envelope_scan_done_tag);
  CHECK(done != nullptr);
  LONGS_EQUAL(77, done->body.scan_done.scan_id);
  LONGS_EQUAL(41 * 11, done->body.scan_done.points);
}

TEST(DeviceResume, RefusesAnUnknownScanAndPointsItNoLongerHas) {
  Bench bench;
  bench.hello(1);
  bench.start_scan();
  bench.run_for(3000000);
  bench.resume(78, 1);
  bench.run_for(100000);
  const digitizer_Envelope* fault = bench.host.last(digitizer_Envelope_fault_tag);
  CHECK(fault != nullptr);
  LONGS_EQUAL(digitizer_FaultCode_FAULT_BAD_REQUEST, fault->body.fault.code);
  STRCMP_CONTAINS("no such scan", fault->body.fault.detail);
  // Point 1 was acknowledged and freed long ago.
  bench.resume(77, 1);
  bench.run_for(100000);
  fault = bench.host.last(digitizer_Envelope_fault_tag);
  STRCMP_CONTAINS("freed", fault->body.fault.detail);
  // The host claims points the device has not measured.
  bench.resume(77, 100000);
  bench.run_for(100000);
  fault = bench.host.last(digitizer_Envelope_fault_tag);
  STRCMP_CONTAINS("not yet measured", fault->body.fault.detail);
}

TEST(DeviceResume, SaysWhenItLacksACapabilityTheHostNeedsAndStillIdentifies) {
  Bench bench;
  bench.hello(1, digitizer_Capability_CAP_DEVICE_FIT | digitizer_Capability_CAP_RESUME);
  bench.run_for(100000);
  const digitizer_Envelope* fault = bench.host.last(digitizer_Envelope_fault_tag);
  CHECK(fault != nullptr);
  LONGS_EQUAL(digitizer_FaultCode_FAULT_UNSUPPORTED, fault->body.fault.code);
  const digitizer_Envelope* hello = bench.host.last(digitizer_Envelope_hello_tag);
  CHECK(hello != nullptr);
  LONGS_EQUAL(digitizer_Capability_CAP_DIGIMATIC | digitizer_Capability_CAP_RESUME, hello->body.hello.capabilities);
}

TEST_GROUP(DeviceSafety){};

TEST(DeviceSafety, AHardLimitStopsTheScanRaisesAnAlarmAndNothingMovesUntilUnlock) {
  // The table starts 0.5 mm beyond where the firmware thinks it is: the scan's first line runs
  // into the x switch.
  dg::sim::SimConfig sim = Bench::sim_config();
  sim.start_x_steps = -150;
  sim.start_y_steps = 0;
  Bench bench(dg::HostSilence::kPause, sim);
  bench.hello(1);
  bench.start_scan();
  bench.run_until_done(600000000);
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_FAULTED, bench.host.done.reason);
  LONGS_EQUAL(digitizer_DeviceState_STATE_ALARM, bench.device.state());
  const digitizer_Envelope* fault = bench.host.last(digitizer_Envelope_fault_tag);
  CHECK(fault != nullptr);
  LONGS_EQUAL(digitizer_FaultCode_FAULT_HARD_LIMIT, fault->body.fault.code);
  STRCMP_CONTAINS("x min limit switch", fault->body.fault.detail);
  CHECK_FALSE(bench.board.drivers_on());
  const int64_t x = bench.board.table_x_steps();
  bench.command(digitizer_CommandKind_CMD_JOG, 30);
  bench.run_for(1000000);
  CHECK(bench.fault_for(30) != nullptr);
  LONGS_EQUAL(digitizer_FaultCode_FAULT_ALARM_LOCKED, bench.fault_for(30)->body.fault.code);
  LONGS_EQUAL(x, bench.board.table_x_steps());
  // Unlock and home: the machine is usable again.
  bench.command(digitizer_CommandKind_CMD_UNLOCK, 31);
  bench.command(digitizer_CommandKind_CMD_HOME, 32);
  bench.run_for(60000000);
  LONGS_EQUAL(digitizer_DeviceState_STATE_IDLE, bench.device.state());
  CHECK(bench.fault_for(32) == nullptr);
  CHECK(bench.board.drivers_on());
  LONGS_EQUAL(0, bench.board.steps_without_drivers());
}

TEST(DeviceSafety, TheEstopEndsTheScanAndUnlockWaitsForItsRelease) {
  dg::sim::SimConfig sim = Bench::sim_config();
  sim.estop_at_ns = 2000000000;   // 2 s into the scan
  sim.estop_for_ns = 10000000000; // held for 10 s
  Bench bench(dg::HostSilence::kPause, sim);
  bench.hello(1);
  bench.start_scan();
  bench.run_until_done(600000000);
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_FAULTED, bench.host.done.reason);
  LONGS_EQUAL(digitizer_FaultCode_FAULT_ESTOP, bench.host.last(digitizer_Envelope_fault_tag)->body.fault.code);
  CHECK(bench.board.now_ns() < 12000000000ull);
  CHECK_FALSE(bench.board.drivers_on());
  bench.command(digitizer_CommandKind_CMD_UNLOCK, 40);
  bench.run_for(100000);
  CHECK(bench.fault_for(40) != nullptr);
  STRCMP_CONTAINS("still pressed", bench.fault_for(40)->body.fault.detail);
  // Released: unlock takes.
  bench.run_for(12000000);
  CHECK(bench.board.now_ns() >= 12000000000ull);
  bench.command(digitizer_CommandKind_CMD_UNLOCK, 41);
  bench.run_for(100000);
  CHECK(bench.fault_for(41) == nullptr);
  LONGS_EQUAL(digitizer_DeviceState_STATE_IDLE, bench.device.state());
  CHECK(bench.board.drivers_on());
  LONGS_EQUAL(0, bench.board.steps_without_drivers());
}

TEST(DeviceSafety, AMachineThatMustHomeRefusesToScanBeforeIt) {
  Bench bench(dg::HostSilence::kPause, Bench::sim_config(), true);
  bench.hello(1);
  bench.start_scan();
  bench.run_for(100000);
  const digitizer_Envelope* fault = bench.fault_for(1);
  CHECK(fault != nullptr);
  LONGS_EQUAL(digitizer_FaultCode_FAULT_NOT_HOMED, fault->body.fault.code);
  bench.command(digitizer_CommandKind_CMD_HOME, 50);
  bench.run_for(60000000);
  bench.host.received.clear();
  bench.start_scan(51);
  bench.run_until_done(600000000);
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_COMPLETED, bench.host.done.reason);
}

TEST(DeviceSafety, SpikesOnTheSafetyInputsNeitherEndAScanNorAlarmTheIdleMachine) {
  // A 2 us spike on the e-stop and limit inputs every 0.7 ms, through homing, a whole scan and the
  // idle time after it: each is read again 20 us later before it counts, so none does.
  dg::sim::SimConfig sim = Bench::sim_config();
  sim.glitch_period_ns = 700000;
  Bench bench(dg::HostSilence::kPause, sim, true);
  bench.hello(1);
  bench.command(digitizer_CommandKind_CMD_HOME, 70);
  bench.run_for(60000000);
  CHECK(bench.fault_for(70) == nullptr);
  bench.host.received.clear();
  bench.start_scan(71);
  bench.run_until_done(600000000);
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_COMPLETED, bench.host.done.reason);
  bench.run_for(5000000);
  LONGS_EQUAL(digitizer_DeviceState_STATE_IDLE, bench.device.state());
  CHECK(bench.host.last(digitizer_Envelope_fault_tag) == nullptr);
}

TEST(DeviceSafety, UnwiredSwitchesAlarmWithTheReasonInsteadOfHoming) {
  dg::sim::SimConfig sim = Bench::sim_config();
  sim.switches = dg::sim::SwitchWiring::kOpen;
  Bench bench(dg::HostSilence::kPause, sim, true);
  bench.hello(1);
  bench.command(digitizer_CommandKind_CMD_HOME, 72);
  bench.run_for(60000000);
  LONGS_EQUAL(digitizer_DeviceState_STATE_ALARM, bench.device.state());
  const digitizer_Envelope* fault = bench.host.last(digitizer_Envelope_fault_tag);
  CHECK(fault != nullptr);
  LONGS_EQUAL(digitizer_FaultCode_FAULT_NOT_HOMED, fault->body.fault.code);
  STRCMP_CONTAINS("still tripped 2 mm off it", fault->body.fault.detail);
  // Still not homed: a scan is refused.
  bench.command(digitizer_CommandKind_CMD_UNLOCK, 73);
  bench.run_for(100000);
  bench.start_scan();
  bench.run_for(100000);
  CHECK(bench.fault_for(1) != nullptr);
  LONGS_EQUAL(digitizer_FaultCode_FAULT_NOT_HOMED, bench.fault_for(1)->body.fault.code);
}

TEST(DeviceSafety, RepeatabilityReadsOnePointAgainAndAgain) {
  dg::sim::SimConfig sim = Bench::sim_config();
  sim.gauge.noise_sigma_mm = 0.003;
  Bench bench(dg::HostSilence::kPause, sim);
  bench.hello(1);
  digitizer_Envelope m = digitizer_Envelope_init_zero;
  m.id = 60;
  m.which_body = digitizer_Envelope_command_tag;
  m.body.command.kind = digitizer_CommandKind_CMD_REPEATABILITY;
  m.body.command.count = 40;
  bench.host.send(m);
  bench.run_for(120000000);
  const digitizer_Envelope* r = bench.host.last(digitizer_Envelope_repeatability_tag);
  CHECK(r != nullptr);
  LONGS_EQUAL(60, r->id);
  LONGS_EQUAL(40, r->body.repeatability.count);
  // The dome's rim is 2 mm high; 3 um noise: the mean within 2 um, the deviation 2-4.5 um.
  CHECK(std::abs(r->body.repeatability.mean_nm - 2000000) <= 2000);
  CHECK(r->body.repeatability.stddev_nm >= 2000 && r->body.repeatability.stddev_nm <= 4500);
  CHECK(r->body.repeatability.min_nm <= r->body.repeatability.mean_nm && r->body.repeatability.mean_nm <= r->body.repeatability.max_nm);
  // The table is back where it started.
  LONGS_EQUAL(0, bench.board.table_x_steps());
  // Out of range counts are refused with the reason.
  m.id = 61;
  m.body.command.count = 1;
  bench.host.send(m);
  bench.run_for(100000);
  CHECK(bench.fault_for(61) != nullptr);
  STRCMP_CONTAINS("2 to 64", bench.fault_for(61)->body.fault.detail);
}

TEST_GROUP(DeviceLink){};

TEST(DeviceLink, ShortensItsBatchesWhileFramesAreLostAndLengthensThemAgain) {
  Bench bench;
  // Long lines, so that points pile up into full batches behind the lost frames.
  bench.request = dg::test::grid_request(77, 0, 120000000, 4000000, 1000000, digitizer_ScanPattern_PATTERN_SERPENTINE);
  bench.hello(1);
  bench.start_scan();
  bench.run_for(2000000);
  auto largest_batch_since = [&](size_t from) { return largest_batch(bench.host.received, from); };
  // One frame in three is lost for a while: once the device has seen its frames resent, its
  // batches are at most two points long.
  bench.wire.drop_every = 3;
  bench.run_for(20000000);
  const size_t lossy_from = bench.host.received.size();
  bench.run_for(40000000);
  CHECK(bench.host.received.size() > lossy_from + 10);
  CHECK(largest_batch_since(lossy_from) <= 2);
  // A clean line again: the batches grow back to as long as a line that never lost a frame
  // gives (a batch goes out when full, at a line's end or once its oldest point is a second old).
  bench.wire.drop_every = 0;
  const size_t clean_from = bench.host.received.size();
  bench.run_until_done(2000000000);
  Bench clean;
  clean.request = bench.request;
  clean.hello(1);
  clean.start_scan();
  clean.run_until_done(2000000000);
  const size_t clean_largest = largest_batch(clean.host.received, 0);
  CHECK(clean_largest > 2);
  // (a backlog left by the lost frames may fill even longer ones while it drains)
  CHECK(largest_batch_since(clean_from) >= clean_largest);
  check_every_point_once(bench.host.stored, 121 * 5);
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_COMPLETED, bench.host.done.reason);
}

TEST(DeviceLink, HelloCarriesTheBoardsWholeName) {
  // The STM32 board says when it runs without its crystal; the name used to be cut at 15 bytes.
  MemoryLink wire;
  dg::sim::SimBoard board(Bench::sim_config(), &wire);
  dg::DeviceConfig config = device_config(dg::HostSilence::kPause);
  config.board = "stm32f411-blackpill (no crystal: HSI clock)";
  dg::Device device(board, config);
  device.begin();
  ScriptedHost host(wire);
  digitizer_Envelope m = digitizer_Envelope_init_zero;
  m.id = 5;
  m.which_body = digitizer_Envelope_host_hello_tag;
  m.body.host_hello.protocol_version = digitizer_ProtocolVersion_PROTOCOL_VERSION;
  m.body.host_hello.min_protocol_version = digitizer_ProtocolVersion_PROTOCOL_VERSION;
  host.send(m, true, 1);
  for (int round = 0; round < 20 && host.last(digitizer_Envelope_hello_tag) == nullptr; ++round) {
    host.exchange();
    device.poll();
    host.exchange();
  }
  const digitizer_Envelope* hello = host.last(digitizer_Envelope_hello_tag);
  CHECK(hello != nullptr);
  STRCMP_EQUAL("stm32f411-blackpill (no crystal: HSI clock)", hello->body.hello.board);
}

TEST_GROUP(DeviceCalibration){};

// The summary a host sets is in every status after it, stored on the board's settings flash, and
// read back by the firmware after a reset; a summary without a version is refused.
TEST(DeviceCalibration, KeepsTheSummaryItIsGivenThroughAResetAndShowsItInStatus) {
  Bench bench;
  size_t stored_bytes = 0;  // the board's flash keeps what it is given, as a file would
  bench.board.on_settings_stored(
      [](const uint8_t*, size_t size, void* context) {
        *static_cast<size_t*>(context) = size;
        return true;
      },
      &stored_bytes);
  bench.hello(1);
  bench.command(digitizer_CommandKind_CMD_STATUS, 2);
  bench.run_for(100000);
  const digitizer_Envelope* before = bench.host.last(digitizer_Envelope_status_tag);
  CHECK(before != nullptr);
  CHECK_FALSE(before->body.status.has_calibration);
  bench.set_calibration(3, 3, 1795000000, 0xdeadbeef,
                        digitizer_CalibrationPart_CALIBRATED_TRAVEL | digitizer_CalibrationPart_CALIBRATED_LEAD);
  bench.command(digitizer_CommandKind_CMD_STATUS, 4);
  bench.run_for(100000);
  CHECK(bench.fault_for(3) == nullptr);
  const digitizer_Envelope* after = bench.host.last(digitizer_Envelope_status_tag);
  CHECK(after != nullptr && after != before);
  CHECK(after->body.status.has_calibration && after->body.status.calibration_kept);
  LONGS_EQUAL(0xdeadbeef, after->body.status.calibration.file_crc32);
  CHECK(stored_bytes > 0);
  bench.restart_firmware();
  bench.new_host();
  bench.hello(2);
  bench.command(digitizer_CommandKind_CMD_STATUS, 5);
  bench.run_for(100000);
  const digitizer_Envelope* restarted = bench.host.last(digitizer_Envelope_status_tag);
  CHECK(restarted != nullptr && restarted != after);
  CHECK(restarted->body.status.has_calibration);
  CHECK(1795000000 == restarted->body.status.calibration.created_unix_s);
  LONGS_EQUAL(3, restarted->body.status.calibration.version);
  bench.set_calibration(6, 0);
  bench.run_for(100000);
  CHECK(bench.fault_for(6) != nullptr);
}

// A board that stores no settings still shows the summary until it restarts, and says it is not kept.
TEST(DeviceCalibration, ABoardThatStoresNothingSaysTheSummaryIsNotKept) {
  Bench bench;
  bench.hello(1);
  bench.set_calibration(2, 1);
  bench.command(digitizer_CommandKind_CMD_STATUS, 3);
  bench.run_for(100000);
  const digitizer_Envelope* status = bench.host.last(digitizer_Envelope_status_tag);
  CHECK(status != nullptr);
  CHECK(status->body.status.has_calibration);
  CHECK_FALSE(status->body.status.calibration_kept);
}

// Resuming for real: a simulated device listening on a socket outlives its hosts; a host process is
// killed with SIGKILL mid-scan, another resumes over a line that corrupts, drops, repeats and has
// its cable pulled three times, and the scan file ends with every point once, in order.
#include <CppUTest/TestHarness.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <vector>
#include <string>
#include <thread>

#include "host/device/capture.h"
#include "host/device/request.h"
#include "host/device/session.h"
#include "host/scan/scan_file.h"
#include "host/transport/sim_transport.h"
#include "host/transport/transport.h"
#include "tests/support/scan_request.h"

namespace {

std::string temp_path(const std::string& name) {
  return std::string(P_tmpdir) + "/dg_resume_" + std::to_string(getpid()) + "_" + name;
}

// digitizer-sim --listen ADDRESS as a child process, stopped with SIGTERM at the end.
class ListeningSim {
 public:
  explicit ListeningSim(const std::string& address) {
    int out[2];
    CHECK(pipe(out) == 0);
    pid_ = fork();
    if (pid_ == 0) {
      dup2(out[1], 1);
      close(out[0]);
      const std::string program = dg::host::find_simulator();
      execl(program.c_str(), program.c_str(), "--listen", address.c_str(), "part=dome", "seed=5", static_cast<char*>(nullptr));
      _exit(127);
    }
    close(out[1]);
    // It says where it listens once the socket is ready.
    char line[128] = {};
    size_t used = 0;
    while (used < sizeof(line) - 1) {
      const ssize_t n = read(out[0], line + used, 1);
      if (n <= 0 || line[used] == '\n') break;
      ++used;
    }
    close(out[0]);
    said_ = line;
    CHECK_TEXT(!said_.empty(), "digitizer-sim did not start listening");
  }
  ~ListeningSim() {
    kill(pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
  const std::string& said() const { return said_; }

 private:
  pid_t pid_ = -1;
  std::string said_;
};

// 161 x 61 points at 0.5 mm, serpentine.
digitizer_ScanRequest long_scan() {
  return dg::test::grid_request(4242, 0, 80000000, 30000000, 500000, digitizer_ScanPattern_PATTERN_SERPENTINE);
}

void check_complete(const dg::host::ScanData& data, const digitizer_ScanRequest& request) {
  const uint32_t per_line = (request.x.max_nm - request.x.min_nm) / request.step_x_nm + 1;
  const uint32_t lines = (request.y.max_nm - request.y.min_nm) / request.step_y_nm + 1;
  LONGS_EQUAL(per_line * lines, data.points.size());
  LONGS_EQUAL(0, data.warnings.size());
  CHECK(data.done.has_value());
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_COMPLETED, data.done->reason);
  LONGS_EQUAL(lines, data.lines.size());
  for (size_t i = 0; i < data.points.size(); ++i) {
    const dg::PointSample& p = data.points[i];
    LONGS_EQUAL(data.points.front().seq + i, p.seq);  // every point once, in order
    const uint32_t line = static_cast<uint32_t>(i / per_line);
    const uint32_t along = static_cast<uint32_t>(i % per_line);
    const uint32_t ix = line % 2 == 0 ? along : per_line - 1 - along;
    LONGS_EQUAL(line, p.line);
    LONGS_EQUAL(static_cast<int32_t>(request.x.min_nm + ix * request.step_x_nm), p.x_nm);
    LONGS_EQUAL(static_cast<int32_t>(request.y.min_nm + line * request.step_y_nm), p.y_nm);
  }
  for (size_t i = 0; i < data.lines.size(); ++i) LONGS_EQUAL(i, data.lines[i].line);
}

off_t file_size(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0 ? st.st_size : 0;
}

// A first host, in a child process, scans `request` into `path` and is killed (SIGKILL) once the
// file holds `bytes`.
void kill_host_scanning(const std::string& uri, const digitizer_ScanRequest& request, const std::string& path, off_t bytes) {
  const pid_t host = fork();
  if (host == 0) {
    try {
      auto transport = dg::host::open_transport(uri);
      dg::host::Session session(*transport);
      const digitizer_Hello hello = session.hello(5000);
      dg::host::ScanFileWriter file(path);
      dg::host::capture_scan(session, hello, request, file, dg::host::CaptureOptions{});
    } catch (...) {
    }
    _exit(0);
  }
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (file_size(path) < bytes && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  kill(host, SIGKILL);
  int status = 0;
  waitpid(host, &status, 0);
  CHECK(WIFSIGNALED(status));
}

dg::host::CaptureResult resume(const std::string& uri, const std::string& path) {
  auto transport = dg::host::open_transport(uri);
  dg::host::Session session(*transport);
  session.hello(5000, digitizer_Capability_CAP_RESUME);
  const dg::host::ScanData stored = dg::host::read_scan_file(path);
  dg::host::ScanFileWriter file = dg::host::ScanFileWriter::continue_file(path, stored.complete_bytes);
  return dg::host::resume_capture(session, stored, file, dg::host::CaptureOptions{});
}

}  // namespace

TEST_GROUP(SimResume){};

TEST(SimResume, EveryPointOnceAfterAKilledHostAndAFaultyLineWithThreePulledCables) {
  const std::string socket_path = temp_path("kill.sock"), path = temp_path("kill.scan");
  ListeningSim sim("unix:" + socket_path);
  const std::string uri = "unix:" + socket_path;
  const digitizer_ScanRequest request = long_scan();
  // Killed once a fifth of the points or so are stored (about 10 bytes a point).
  kill_host_scanning(uri, request, path, 20000);
  const dg::host::ScanData before = dg::host::read_scan_file(path);
  CHECK(!before.done.has_value());
  CHECK(!before.points.empty());

  const dg::host::CaptureResult result =
      resume("fault:corrupt=0.001,drop=0.01,dup=0.01,disconnects=3,every=150,seed=11;" + uri, path);
  // The cable is pulled every 150 host writes, and the host writes acknowledgements in batches
  // timed by the clock: under load (sanitizers, a busy machine) the rest of the scan can take
  // fewer than 450 writes, so not every pull may come. At least one must, and each is survived.
  CHECK(result.reconnects >= 1 && result.reconnects <= 3);
  CHECK(result.finished);
  check_complete(dg::host::read_scan_file(path), request);
  std::remove(path.c_str());
}

TEST(SimResume, AStopOnRequestPausesTheDeviceAndTheScanResumesLater) {
  const std::string socket_path = temp_path("stop.sock"), path = temp_path("stop.scan");
  ListeningSim sim("unix:" + socket_path);
  const std::string uri = "unix:" + socket_path;
  const digitizer_ScanRequest request = long_scan();
  {
    auto transport = dg::host::open_transport(uri);
    dg::host::Session session(*transport);
    const digitizer_Hello hello = session.hello(5000);
    dg::host::ScanFileWriter file(path);
    dg::host::CaptureOptions options;
    uint32_t seen = 0;
    options.progress = [&seen](const dg::host::CaptureProgress& p) { seen = p.points; };
    options.stop_requested = [&seen] { return seen >= 2000; };
    const dg::host::CaptureResult result = dg::host::capture_scan(session, hello, request, file, options);
    CHECK(result.interrupted);
    CHECK(!result.finished);
    // The device waits, paused, for the host to come back.
    digitizer_Envelope status = digitizer_Envelope_init_zero;
    status.which_body = digitizer_Envelope_command_tag;
    status.body.command.kind = digitizer_CommandKind_CMD_STATUS;
    const digitizer_Envelope reply = dg::host::request(session, status, 2000);
    LONGS_EQUAL(digitizer_Envelope_status_tag, reply.which_body);
    LONGS_EQUAL(digitizer_DeviceState_STATE_PAUSED, reply.body.status.state);
  }
  const dg::host::CaptureResult result = resume(uri, path);
  CHECK(result.finished);
  check_complete(dg::host::read_scan_file(path), request);
  std::remove(path.c_str());
}

TEST(SimResume, ScansOverTcp) {
  ListeningSim sim("tcp:0");
  int port = 0;
  CHECK(std::sscanf(sim.said().c_str(), "listening on tcp port %d", &port) == 1);
  const std::string path = temp_path("tcp.scan");
  const digitizer_ScanRequest request = dg::test::grid_request(5, 0, 20000000, 10000000, 1000000, digitizer_ScanPattern_PATTERN_RASTER);
  auto transport = dg::host::open_transport("tcp:127.0.0.1:" + std::to_string(port));
  dg::host::Session session(*transport);
  const digitizer_Hello hello = session.hello(5000);
  {
    dg::host::ScanFileWriter file(path);
    CHECK(dg::host::capture_scan(session, hello, request, file, dg::host::CaptureOptions{}).finished);
  }
  const dg::host::ScanData data = dg::host::read_scan_file(path);
  LONGS_EQUAL(21 * 11, data.points.size());
  std::remove(path.c_str());
}

TEST(SimResume, ResumingAScanTheDeviceDoesNotHaveIsAClearError) {
  const std::string socket_path = temp_path("none.sock"), path = temp_path("none.scan");
  ListeningSim sim("unix:" + socket_path);
  {
    dg::host::ScanFileWriter file(path);
    digitizer_Envelope start = digitizer_Envelope_init_zero;
    start.which_body = digitizer_Envelope_scan_request_tag;
    start.body.scan_request = long_scan();
    file.append(start);
  }
  std::string error;
  try {
    resume("unix:" + socket_path, path);
  } catch (const dg::host::ScanRefused& e) {
    error = e.what();
  }
  STRCMP_CONTAINS("cannot resume", error.c_str());
  STRCMP_CONTAINS("no such scan", error.c_str());
  std::remove(path.c_str());
}

TEST(SimResume, ANewScanKeepsNoneOfTheLastScansUnacknowledgedPoints) {
  const std::string socket_path = temp_path("tail.sock"), path = temp_path("tail.scan");
  ListeningSim sim("unix:" + socket_path);
  const std::string uri = "unix:" + socket_path;
  const digitizer_ScanRequest first = dg::test::grid_request(1, 0, 20000000, 10000000, 1000000, digitizer_ScanPattern_PATTERN_RASTER);
  {
    // A host that never acknowledges the last line (its final PointAck lost, say): those points
    // stay in the device's ring and are replayed to the next host.
    auto transport = dg::host::open_transport(uri);
    dg::host::Session session(*transport);
    session.hello(5000);
    digitizer_Envelope start = digitizer_Envelope_init_zero;
    start.which_body = digitizer_Envelope_scan_request_tag;
    start.body.scan_request = first;
    session.send(start);
    digitizer_Envelope message;
    bool done = false;
    while (!done && session.receive(&message, 5000)) {
      done = message.which_body == digitizer_Envelope_scan_done_tag;
      if (message.which_body != digitizer_Envelope_points_tag || message.body.points.line == 10) continue;
      digitizer_Envelope ack = digitizer_Envelope_init_zero;
      ack.which_body = digitizer_Envelope_point_ack_tag;
      ack.body.point_ack.seq = message.body.points.first_seq + message.body.points.dx_nm_count - 1;
      session.send(ack);
    }
    CHECK(done);
  }
  const digitizer_ScanRequest second = long_scan();
  auto transport = dg::host::open_transport(uri);
  dg::host::Session session(*transport);
  const digitizer_Hello hello = session.hello(5000);
  {
    dg::host::ScanFileWriter file(path);
    CHECK(dg::host::capture_scan(session, hello, second, file, dg::host::CaptureOptions{}).finished);
  }
  const dg::host::ScanData data = dg::host::read_scan_file(path);
  check_complete(data, second);
  LONGS_EQUAL(21 * 11 + 1, data.points.front().seq);  // the first scan had seqs 1..231
  std::remove(path.c_str());
}

namespace {

// The scan file of a host whose power fails: records reach the real file, the sizes at each sync
// are noted, and after `records` appends the "power" goes at the first append that finds records
// not yet synced (append throws, the capture stops, no acknowledgement follows), so there is a
// tail to lose whatever the timing (a slow host syncs on every quiet moment). What was synced is
// on the disk; anything after it may be lost.
class PowerFailingSink : public dg::host::ScanSink {
 public:
  PowerFailingSink(dg::host::ScanFileWriter& file, size_t records) : file_(file), records_left_(records) {}
  void append(const digitizer_Envelope& message) override {
    if (records_left_ == 0 && file_.bytes_written() > synced_bytes_) throw dg::host::ScanFileError("the power failed");
    if (records_left_ > 0) --records_left_;
    file_.append(message);
  }
  void sync() override {
    file_.sync();
    synced_bytes_ = file_.bytes_written();
  }
  void accepted() override { file_.accepted(); }
  const std::string& path() const override { return file_.path(); }
  uint64_t synced_bytes() const { return synced_bytes_; }

 private:
  dg::host::ScanFileWriter& file_;
  size_t records_left_;
  uint64_t synced_bytes_ = 0;
};

// Scans `request` into `path` from the device at `uri` until the power fails after `records`
// records; *synced is the file's size at its last sync, *written its size when the power went.
void scan_until_the_power_fails(const std::string& uri, const digitizer_ScanRequest& request, size_t records,
                                const std::string& path, uint64_t* synced, uint64_t* written) {
  auto transport = dg::host::open_transport(uri);
  dg::host::Session session(*transport);
  const digitizer_Hello hello = session.hello(5000);
  dg::host::ScanFileWriter file = dg::host::ScanFileWriter::when_accepted(path, false);
  PowerFailingSink sink(file, records);
  CHECK_THROWS(dg::host::ScanFileError, dg::host::capture_scan(session, hello, request, sink, dg::host::CaptureOptions{}));
  *synced = sink.synced_bytes();
  *written = file.bytes_written();
}

// Scans until the power fails after `records` records, cuts the file `cut` bytes after the last
// sync (a negative `cut`: that many bytes before the end, but not before the sync), and resumes:
// every point must still be had, since the device was told only of points that were synced.
void check_power_loss(size_t records, int64_t cut, const char* name) {
  const std::string socket_path = temp_path(std::string(name) + ".sock"), path = temp_path(std::string(name) + ".scan");
  std::remove(path.c_str());
  ListeningSim sim("unix:" + socket_path);
  const std::string uri = "unix:" + socket_path;
  const digitizer_ScanRequest request = long_scan();
  uint64_t synced = 0, written = 0;
  scan_until_the_power_fails(uri, request, records, path, &synced, &written);
  CHECK(written > synced);  // an unsynced tail exists to lose
  const uint64_t keep = cut >= 0 ? std::min<uint64_t>(written, synced + static_cast<uint64_t>(cut))
                                 : std::max<uint64_t>(synced, written - static_cast<uint64_t>(-cut));
  CHECK(truncate(path.c_str(), static_cast<off_t>(keep)) == 0);
  try {
    const dg::host::CaptureResult result = resume(uri, path);
    CHECK(result.finished);
    check_complete(dg::host::read_scan_file(path), request);
  } catch (const std::exception& e) {
    std::remove(path.c_str());
    FAIL(e.what());  // "acknowledged and freed": the device was told of points the disk lost
  }
  std::remove(path.c_str());
}

// A resuming host whose power fails again at the first points it is sent, before it syncs: the
// device is told of nothing and keeps them. Remembers where those points began.
class FirstPointsSink : public dg::host::ScanSink {
 public:
  void append(const digitizer_Envelope& message) override {
    if (message.which_body != digitizer_Envelope_points_tag) return;
    first_seq = message.body.points.first_seq;
    throw dg::host::ScanFileError("the power failed again");
  }
  void sync() override {}
  const std::string& path() const override { return path_; }
  uint32_t first_seq = 0;

 private:
  std::string path_ = "resumed.scan";
};

// Resumes the scan in `path` and returns the sequence number of the first point the device sends
// for it (0: none came).
uint32_t first_point_resumed(const std::string& uri, const std::string& path) {
  auto transport = dg::host::open_transport(uri);
  dg::host::Session session(*transport);
  session.hello(5000, digitizer_Capability_CAP_RESUME);
  const dg::host::ScanData stored = dg::host::read_scan_file(path);
  FirstPointsSink sink;
  CHECK_THROWS(dg::host::ScanFileError, dg::host::resume_capture(session, stored, sink, dg::host::CaptureOptions{}));
  return sink.first_seq;
}

}  // namespace

// The same at every byte of the tail a power loss may take: whatever it leaves (a cut record, whole
// records, none of the tail), the device still has the next point the file lacks, and sends it.
TEST(SimResume, APowerLossCutAtEveryByteOfTheUnsyncedTailLosesNoPoint) {
  const std::string socket_path = temp_path("everycut.sock"), path = temp_path("everycut.scan"),
                    copy = temp_path("everycut-copy.scan");
  std::remove(path.c_str());
  ListeningSim sim("unix:" + socket_path);
  const std::string uri = "unix:" + socket_path;
  uint64_t synced = 0, written = 0;
  scan_until_the_power_fails(uri, long_scan(), 400, path, &synced, &written);
  CHECK(written > synced);
  std::ifstream in(path, std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  LONGS_EQUAL(written, bytes.size());
  size_t cuts = 0;
  // Cuts from the sync up, so each resume asks for no point before the last one's.
  for (uint64_t keep = synced; keep <= written; ++keep, ++cuts) {
    {
      std::ofstream out(copy, std::ios::binary | std::ios::trunc);
      out.write(bytes.data(), static_cast<std::streamsize>(keep));
    }
    const dg::host::ScanData stored = dg::host::read_scan_file(copy);
    CHECK(!stored.points.empty());
    const uint32_t next = stored.points.back().seq + 1;
    LONGS_EQUAL(next, first_point_resumed(uri, copy));
  }
  CHECK(cuts > 1);
  std::remove(copy.c_str());
  std::remove(path.c_str());
}

// A power loss keeps what was synced and may lose everything after it: cut exactly there, in the
// middle of the next record, and 7 bytes before the end, the resume finds every point.
TEST(SimResume, APowerLossLosesNoPointTheDeviceWasToldIsStored) {
  check_power_loss(300, 0, "power0");
  check_power_loss(377, 5, "power5");
  check_power_loss(450, -7, "power7");
}

// A second host (`digitizer status` from another terminal) while a scan runs is turned away with
// the reason, as a claimed USB interface would turn it away; it used to take the link over, and
// the scanning host lost points reconnecting.
TEST(SimResume, ASecondHostIsTurnedAwayAndTheScanGoesOnUndisturbed) {
  const std::string socket_path = temp_path("second.sock"), path = temp_path("second.scan");
  ListeningSim sim("unix:" + socket_path);
  const std::string uri = "unix:" + socket_path;
  const digitizer_ScanRequest request = long_scan();
  dg::host::CaptureResult result;
  std::thread scanning([&] {
    auto transport = dg::host::open_transport(uri);
    dg::host::Session session(*transport);
    const digitizer_Hello hello = session.hello(5000);
    dg::host::ScanFileWriter file(path);
    result = dg::host::capture_scan(session, hello, request, file, dg::host::CaptureOptions{});
  });
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (file_size(path) < 20000 && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  std::string error;
  for (int attempt = 0; attempt < 3; ++attempt) {
    try {
      auto transport = dg::host::open_transport(uri);
      dg::host::Session session(*transport);
      session.hello(2000);
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  scanning.join();
  STRCMP_CONTAINS("another host is probably connected", error.c_str());
  CHECK(result.finished);
  LONGS_EQUAL(0, result.reconnects);
  check_complete(dg::host::read_scan_file(path), request);
  std::remove(path.c_str());
}

TEST(SimResume, AFlyScanKilledMidLineResumesWithEveryMeasuredPointOnce) {
  const std::string socket_path = temp_path("fly.sock"), path = temp_path("fly.scan");
  ListeningSim sim("unix:" + socket_path);
  const std::string uri = "unix:" + socket_path;
  digitizer_ScanRequest request = dg::test::grid_request(4343, 0, 40000000, 30000000, 200000, digitizer_ScanPattern_PATTERN_SERPENTINE);
  request.step_y_nm = 1000000;
  request.feed_um_s = 0;
  request.mode = digitizer_ScanMode_SCAN_MODE_FLY;
  kill_host_scanning(uri, request, path, 15000);
  CHECK(!dg::host::read_scan_file(path).done.has_value());

  const dg::host::CaptureResult result = resume(uri, path);
  CHECK(result.finished);
  const dg::host::ScanData data = dg::host::read_scan_file(path);
  std::remove(path.c_str());
  LONGS_EQUAL(0, data.warnings.size());
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_COMPLETED, data.done->reason);
  LONGS_EQUAL(31, data.lines.size());
  // Every point once, in order; each line one way (serpentine), ending on its line-end flag.
  std::printf("\n  a fly scan killed and resumed: %zu points (uninterrupted: 6541)\n", data.points.size());
  CHECK(data.points.size() > 31 * 150);
  for (size_t i = 1; i < data.points.size(); ++i) {
    const dg::PointSample& a = data.points[i - 1];
    const dg::PointSample& b = data.points[i];
    LONGS_EQUAL(a.seq + 1, b.seq);
    if (a.line == b.line) {
      CHECK(a.line % 2 == 0 ? b.x_nm > a.x_nm : b.x_nm < a.x_nm);
      // No gap: a line the device ran while its ring was full is flown again from the gap.
      CHECK(std::abs(b.x_nm - a.x_nm) <= 2 * static_cast<int32_t>(request.step_x_nm));
    } else {
      LONGS_EQUAL(a.line + 1, b.line);
      CHECK(a.flags & digitizer_PointFlag_POINT_LINE_END);
    }
  }
}

// The whole system in simulation: host capture code -> sim: transport -> firmware on the
// simulated board -> pin-level gauge over a virtual part, and back into a scan file.
#include <CppUTest/TestHarness.h>

#include <dirent.h>
#include <unistd.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "host/device/capture.h"
#include "host/device/session.h"
#include "host/scan/scan_file.h"
#include "host/transport/transport.h"
#include "hw/sim/parts.h"
#include "tests/support/scan_request.h"

namespace {

std::string temp_path(const std::string& name) {
  return std::string(P_tmpdir) + "/dg_system_" + std::to_string(getpid()) + "_" + name;
}

digitizer_ScanRequest grid_41_by_31(digitizer_ScanPattern pattern) {
  return dg::test::grid_request(7, 0, 40000000, 30000000, 1000000, pattern);
}

// Opens the device, says hello and captures the scan into `path`; DeviceError passes through.
dg::host::CaptureResult capture_to(const std::string& uri, const digitizer_ScanRequest& request, const std::string& path) {
  auto transport = dg::host::open_transport(uri);
  dg::host::Session session(*transport);
  const digitizer_Hello hello = session.hello(5000);
  dg::host::ScanFileWriter file = dg::host::ScanFileWriter::when_accepted(path, true);
  return dg::host::capture_scan(session, hello, request, file, dg::host::CaptureOptions{});
}

dg::host::ScanData scan(const std::string& uri, const digitizer_ScanRequest& request, const std::string& path) {
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_COMPLETED, capture_to(uri, request, path).done.reason);
  return dg::host::read_scan_file(path);
}

// `faults`: empty for a clean line, else fault: options put in front of the sim: URI.
void check_grid_scan(const char* part_name, digitizer_ScanPattern pattern, const std::string& faults = "") {
  const std::string path = temp_path(std::string(part_name) + ".scan");
  const std::string sim = std::string("sim:seed=3,part=") + part_name;
  const dg::host::ScanData data = scan(faults.empty() ? sim : "fault:" + faults + ";" + sim, grid_41_by_31(pattern), path);
  std::remove(path.c_str());
  dg::sim::PartKind kind;
  CHECK(dg::sim::parse_part(part_name, &kind));
  dg::sim::Part part;
  part.kind = kind;

  LONGS_EQUAL(41 * 31, data.points.size());
  LONGS_EQUAL(0, data.warnings.size());
  CHECK(data.done.has_value());
  LONGS_EQUAL(31, data.lines.size());
  for (size_t i = 0; i < data.points.size(); ++i) {
    const dg::PointSample& p = data.points[i];
    // Every point once, in order, on its grid node, in the pattern's order.
    LONGS_EQUAL(data.points[0].seq + i, p.seq);
    const uint32_t line = static_cast<uint32_t>(i / 41);
    const uint32_t along = static_cast<uint32_t>(i % 41);
    const bool reverse = pattern == digitizer_ScanPattern_PATTERN_SERPENTINE && (line & 1u);
    LONGS_EQUAL(line, p.line);
    LONGS_EQUAL(static_cast<int32_t>((reverse ? 40 - along : along) * 1000000), p.x_nm);
    LONGS_EQUAL(static_cast<int32_t>(line * 1000000), p.y_nm);
    // z is the part's height within the gauge's resolution (1 um, rounded: 0.5 um).
    const double expected_nm = part.height_mm(p.x_nm * 1e-6, p.y_nm * 1e-6) * 1e6;
    CHECK_TEXT(std::fabs(p.z_nm - expected_nm) <= 500.0 + 1e-6, part_name);
  }
}

}  // namespace

TEST_GROUP(SimScan){};

TEST(SimScan, DomeArrivesCompleteAndExact) {
  check_grid_scan("dome", digitizer_ScanPattern_PATTERN_SERPENTINE);
}

TEST(SimScan, SaddleArrivesCompleteAndExact) {
  check_grid_scan("saddle", digitizer_ScanPattern_PATTERN_RASTER);
}

TEST(SimScan, CanisterArrivesCompleteAndExact) {
  check_grid_scan("canister", digitizer_ScanPattern_PATTERN_SERPENTINE);
}

TEST(SimScan, LosesNothingOverALineThatCorruptsDropsRepeatsAndGoesDead) {
  // One byte in a thousand flipped each way, 1 % of frames lost and 1 % sent twice, and three
  // 200 ms outages: every point arrives once, in order, on its grid node, with the right height.
  check_grid_scan("dome", digitizer_ScanPattern_PATTERN_SERPENTINE,
                  "corrupt=0.001,drop=0.01,dup=0.01,outages=3,outage_ms=200,every=150,seed=5");
}

namespace {

// An 11 x 6 raster at 1 mm through `faults`: every point once, in order, on its node, exact.
void check_small_scan_through(const std::string& faults) {
  const std::string path = temp_path("faulty.scan");
  const digitizer_ScanRequest request = dg::test::grid_request(7, 0, 10000000, 5000000, 1000000, digitizer_ScanPattern_PATTERN_RASTER);
  const dg::host::ScanData data = scan("fault:" + faults + ";sim:seed=3,part=dome", request, path);
  std::remove(path.c_str());
  dg::sim::Part part;
  part.kind = dg::sim::PartKind::kDome;
  LONGS_EQUAL(11 * 6, data.points.size());
  LONGS_EQUAL(6, data.lines.size());
  for (size_t i = 0; i < data.points.size(); ++i) {
    const dg::PointSample& p = data.points[i];
    LONGS_EQUAL(data.points[0].seq + i, p.seq);
    LONGS_EQUAL(static_cast<int32_t>((i % 11) * 1000000), p.x_nm);
    LONGS_EQUAL(static_cast<int32_t>((i / 11) * 1000000), p.y_nm);
    const double expected_nm = part.height_mm(p.x_nm * 1e-6, p.y_nm * 1e-6) * 1e6;
    CHECK(std::fabs(p.z_nm - expected_nm) <= 500.0 + 1e-6);
  }
}

}  // namespace

TEST(SimScan, RidesOutALineThatDamagesTwoBytesInEveryHundred) {
  // At 2 % a full 16-point batch (about 290 bytes on the wire) arrives whole 3 times in 1000:
  // the device shortens its batches while frames are resent, the host keeps the frames that
  // arrive after a lost one, and a device whose frames arrive damaged is not taken for silent.
  check_small_scan_through("corrupt=0.02,seed=4");
}

TEST(SimScan, RidesOutALineThatLosesOneFrameInFive) {
  check_small_scan_through("drop=0.2,seed=4");
}

TEST(SimScan, SameSeedGivesTheSameScan) {
  const std::string a = temp_path("a.scan"), b = temp_path("b.scan");
  digitizer_ScanRequest r = grid_41_by_31(digitizer_ScanPattern_PATTERN_SERPENTINE);
  r.x.max_nm = 10000000;
  r.y.max_nm = 5000000;
  const dg::host::ScanData first = scan("sim:part=dome,seed=11,noise_um=3,outliers=0.05", r, a);
  const dg::host::ScanData second = scan("sim:part=dome,seed=11,noise_um=3,outliers=0.05", r, b);
  const dg::host::ScanData other = scan("sim:part=dome,seed=12,noise_um=3,outliers=0.05", r, b);
  std::remove(a.c_str());
  std::remove(b.c_str());
  LONGS_EQUAL(first.points.size(), second.points.size());
  bool differs_from_other = false;
  for (size_t i = 0; i < first.points.size(); ++i) {
    LONGS_EQUAL(first.points[i].z_nm, second.points[i].z_nm);
    CHECK(first.points[i].t_us == second.points[i].t_us);
    if (first.points[i].z_nm != other.points[i].z_nm) differs_from_other = true;
  }
  CHECK(differs_from_other);
}

TEST(SimScan, RefusesAScanOutsideTheTable) {
  const std::string path = temp_path("refused.scan");
  digitizer_ScanRequest r = grid_41_by_31(digitizer_ScanPattern_PATTERN_RASTER);
  r.x.max_nm = 900000000;
  try {
    scan("sim:part=flat", r, path);
    FAIL("scan outside the table was accepted");
  } catch (const dg::host::DeviceError& e) {
    CHECK(std::string(e.what()).find("soft limit") != std::string::npos);
  }
  std::remove(path.c_str());
}

// A scan the device refuses leaves the record that was there untouched (even asked to replace it),
// creates nothing where there was nothing, and leaves no hidden file behind.
TEST(SimScan, ARefusedScanLeavesNoFileAndAnExistingOneUntouched) {
  const std::string kept = temp_path("kept.scan"), fresh = temp_path("fresh.scan");
  {
    std::FILE* f = std::fopen(kept.c_str(), "wb");
    std::fputs("an earlier scan", f);
    std::fclose(f);
  }
  digitizer_ScanRequest r = grid_41_by_31(digitizer_ScanPattern_PATTERN_RASTER);
  r.x.max_nm = 900000000;
  for (const std::string& path : {kept, fresh}) {
    CHECK_THROWS(dg::host::ScanRefused, capture_to("sim:part=flat", r, path));
  }
  std::FILE* f = std::fopen(kept.c_str(), "rb");
  char text[32] = {};
  CHECK(f != nullptr && std::fread(text, 1, sizeof text - 1, f) > 0);
  if (f) std::fclose(f);
  STRCMP_EQUAL("an earlier scan", text);
  CHECK(access(fresh.c_str(), F_OK) != 0);
  // No ".kept.scan.XXXXXX" or ".fresh.scan.XXXXXX" is left in the directory.
  const std::string dir = std::string(P_tmpdir);
  bool leftover = false;
  if (DIR* d = opendir(dir.c_str())) {
    while (const dirent* entry = readdir(d)) {
      const std::string name = entry->d_name;
      const std::string pid = std::to_string(getpid());
      leftover |= name.rfind(".dg_system_" + pid, 0) == 0;
    }
    closedir(d);
  }
  CHECK(!leftover);
  std::remove(kept.c_str());
}

// Two hosts scanning into one file: the second cannot open it while the first writes.
TEST(SimScan, ASecondWriterOfAScanFileIsRefused) {
  const std::string path = temp_path("shared.scan");
  std::remove(path.c_str());
  dg::host::ScanFileWriter first(path);
  try {
    dg::host::ScanFileWriter second = dg::host::ScanFileWriter::continue_file(path, 0);
    FAIL("a second writer was let in");
  } catch (const dg::host::ScanFileError& e) {
    STRCMP_CONTAINS("another digitizer process is writing", e.what());
  }
  CHECK_THROWS(dg::host::ScanFileError, dg::host::ScanFileWriter::when_accepted(path, true));
  CHECK_THROWS(dg::host::ScanFileError, dg::host::ScanFileWriter(path));
  std::remove(path.c_str());
}

TEST(SimScan, ABadSimulatorOptionIsAClearError) {
  try {
    auto transport = dg::host::open_transport("sim:part=teapot");
    dg::host::Session session(*transport);
    session.hello(3000);
    FAIL("unknown part accepted");
  } catch (const dg::host::TransportError& e) {
    CHECK(std::string(e.what()).find("status 2") != std::string::npos);
  }
}

TEST(SimScan, AFaultyGaugeStopsTheScanWithAFaultAndKeepsThePoints) {
  // A gauge that never answers: every read and retry times out.
  const std::string path = temp_path("fault.scan");
  digitizer_ScanRequest r = grid_41_by_31(digitizer_ScanPattern_PATTERN_RASTER);
  r.x.max_nm = 3000000;
  r.y.max_nm = 0;
  const dg::host::CaptureResult result = capture_to("sim:part=flat,mute=1", r, path);
  std::remove(path.c_str());
  LONGS_EQUAL(digitizer_ScanEnd_SCAN_FAULTED, result.done.reason);
  LONGS_EQUAL(0, result.points);
}

TEST(SimScan, ASilentDeviceIsNoticedWithinASecondAndThePointsAreKept) {
  // The line goes dead for 5 s after a few frames: the heartbeat finds the device silent.
  const std::string path = temp_path("silent.scan");
  const auto started = std::chrono::steady_clock::now();
  std::string error;
  try {
    capture_to("fault:outages=1,outage_ms=5000,every=30;sim:part=flat", grid_41_by_31(digitizer_ScanPattern_PATTERN_RASTER), path);
  } catch (const dg::host::DeviceError& e) {
    error = e.what();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  STRCMP_CONTAINS("device silent for", error.c_str());
  CHECK(seconds < 3.0);
  // What arrived before the line died is in the file.
  const dg::host::ScanData data = dg::host::read_scan_file(path);
  std::remove(path.c_str());
  CHECK(data.points.size() > 0);
}

TEST(SimScan, ACaliperOnTheGaugePortScansWithinItsResolution) {
  // A 24-bit caliper reads to 0.01 mm and only 8 times a second: a small grid.
  const std::string path = temp_path("caliper.scan");
  digitizer_ScanRequest request = dg::test::grid_request(9, 0, 10000000, 5000000, 1000000, digitizer_ScanPattern_PATTERN_RASTER);
  request.probe = digitizer_ProbeType_PROBE_CALIPER_24BIT;
  const dg::host::ScanData data = scan("sim:part=dome,gauge=caliper", request, path);
  std::remove(path.c_str());
  LONGS_EQUAL(11 * 6, data.points.size());
  dg::sim::Part part;
  part.kind = dg::sim::PartKind::kDome;
  for (const dg::PointSample& p : data.points) {
    const double expected_nm = part.height_mm(p.x_nm * 1e-6, p.y_nm * 1e-6) * 1e6;
    CHECK(std::fabs(p.z_nm - expected_nm) <= 5000.0 + 1e-6);
  }
  // The Digimatic request is refused by a device whose port holds a caliper, with its reason.
  request.probe = digitizer_ProbeType_PROBE_DIGIMATIC;
  std::string error;
  try {
    capture_to("sim:part=dome,gauge=caliper", request, path);
  } catch (const dg::host::DeviceError& e) {
    error = e.what();
  }
  std::remove(path.c_str());
  STRCMP_CONTAINS("gauge is a 24-bit caliper", error.c_str());
}

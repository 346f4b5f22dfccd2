// Scan files: round trip, a cut-off tail loses only itself, damage is named by offset.
#include "host/scan/scan_file.h"

#include "common/proto/messages.h"
#include "host/scan/point_reader.h"

#include <CppUTest/TestHarness.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

std::string temp_path(const char* name) {
  return std::string(P_tmpdir) + "/dg_test_" + std::to_string(getpid()) + "_" + name;
}

digitizer_Envelope batch_message(uint32_t first_seq, uint32_t count, uint32_t line) {
  digitizer_Envelope m = digitizer_Envelope_init_zero;
  m.which_body = digitizer_Envelope_points_tag;
  dg::point_batch_begin(&m.body.points, first_seq, line);
  for (uint32_t i = 0; i < count; ++i) {
    dg::PointSample p;
    p.seq = first_seq + i;
    p.line = line;
    p.x_nm = static_cast<int32_t>(i * 1000000);
    p.y_nm = static_cast<int32_t>(line * 1000000);
    p.z_nm = static_cast<int32_t>(2000000 + i * 7);
    p.t_us = 1000 * (first_seq + i);
    CHECK(dg::point_batch_append(&m.body.points, p) == dg::Status::kOk);
  }
  return m;
}

std::vector<char> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_bytes(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

TEST_GROUP(ScanFile) {
  std::string path;
  void setup() override { path = temp_path("scan.scan"); }
  void teardown() override { std::remove(path.c_str()); }
  void write_three_batches() {
    dg::host::ScanFileWriter writer(path);
    digitizer_Envelope hello = digitizer_Envelope_init_zero;
    hello.which_body = digitizer_Envelope_hello_tag;
    dg::set_string(hello.body.hello.device_id, "DG-7");
    writer.append(hello);
    writer.append(batch_message(1, 16, 0));
    writer.append(batch_message(17, 5, 0));
    writer.append(batch_message(22, 16, 1));
  }
};

TEST(ScanFile, RoundTripsEveryPoint) {
  write_three_batches();
  const dg::host::ScanData data = dg::host::read_scan_file(path);
  CHECK(data.device.has_value());
  STRCMP_EQUAL("DG-7", data.device->device_id);
  LONGS_EQUAL(37, data.points.size());
  for (size_t i = 0; i < data.points.size(); ++i) LONGS_EQUAL(i + 1, data.points[i].seq);
  LONGS_EQUAL(0, data.warnings.size());
  LONGS_EQUAL(4, data.records);
}

TEST(ScanFile, ACutOffLastRecordLosesOnlyItself) {
  write_three_batches();
  std::vector<char> bytes = read_bytes(path);
  // Every possible cut inside the last record keeps the first 21 points.
  const dg::host::ScanData full = dg::host::read_scan_file(path);
  for (size_t cut = 1; cut < 20; ++cut) {
    write_bytes(path, std::vector<char>(bytes.begin(), bytes.end() - static_cast<long>(cut)));
    const dg::host::ScanData data = dg::host::read_scan_file(path);
    LONGS_EQUAL(21, data.points.size());
    LONGS_EQUAL(1, data.warnings.size());
  }
  LONGS_EQUAL(37, full.points.size());
}

TEST(ScanFile, DamageInTheMiddleIsAnErrorNamingTheOffset) {
  write_three_batches();
  std::vector<char> bytes = read_bytes(path);
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x5A);
  write_bytes(path, bytes);
  try {
    dg::host::read_scan_file(path);
    FAIL("damage not detected");
  } catch (const dg::host::ScanFileError& e) {
    const std::string message = e.what();
    CHECK(message.find(path) != std::string::npos);
    CHECK(message.find("at byte") != std::string::npos);
  }
}

TEST(ScanFile, RefusesAFileThatIsNotAScan) {
  write_bytes(path, {'x', ',', 'y', ',', 'z', '\n', '1', ',', '2'});
  CHECK_THROWS(dg::host::ScanFileError, dg::host::read_scan_file(path));
}

TEST(ScanFile, RefusesAMissingFile) {
  CHECK_THROWS(dg::host::ScanFileError, dg::host::read_scan_file(path + ".missing"));
}

TEST(ScanFile, KeepsDuplicatedPointsOnce) {
  {
    dg::host::ScanFileWriter writer(path);
    writer.append(batch_message(1, 4, 0));
    writer.append(batch_message(3, 4, 0));  // overlaps 3..4
  }
  const dg::host::ScanData data = dg::host::read_scan_file(path);
  LONGS_EQUAL(6, data.points.size());
  LONGS_EQUAL(6, data.points.back().seq);
}

// Two scan files joined (cat a b > c) read as one scan would be two scans' points mixed: refused.
TEST(ScanFile, RefusesTwoScansJoinedIntoOneFile) {
  write_three_batches();
  std::vector<char> bytes = read_bytes(path);
  std::vector<char> twice = bytes;
  twice.insert(twice.end(), bytes.begin(), bytes.end());
  write_bytes(path, twice);
  try {
    dg::host::read_scan_file(path);
    FAIL("a doubled scan file was read as one scan");
  } catch (const dg::host::ScanFileError& e) {
    STRCMP_CONTAINS("two scan files joined", e.what());
  }
}

// The repeatability measured before a scan is a record of its file, read back with the points,
// which then carry a standard uncertainty (also through the point reader).
TEST(ScanFile, KeepsTheRepeatabilityMeasuredBeforeTheScan) {
  {
    dg::host::ScanFileWriter writer(path);
    digitizer_Envelope hello = digitizer_Envelope_init_zero;
    hello.which_body = digitizer_Envelope_hello_tag;
    hello.body.hello.gauge_resolution_nm = 1000;
    writer.append(hello);
    digitizer_Envelope r = digitizer_Envelope_init_zero;
    r.which_body = digitizer_Envelope_repeatability_tag;
    r.body.repeatability.count = 30;
    r.body.repeatability.stddev_nm = 4000;
    writer.append(r);
    writer.append(batch_message(1, 16, 0));
  }
  const dg::host::ScanData data = dg::host::read_scan_file(path);
  CHECK(data.repeatability.has_value());
  LONGS_EQUAL(30, data.repeatability->count);
  LONGS_EQUAL(4000, data.repeatability->stddev_nm);
  const std::string csv_named = path + ".scan";
  std::rename(path.c_str(), csv_named.c_str());
  const dg::host::PointCloud cloud = dg::host::read_points(csv_named);
  std::remove(csv_named.c_str());
  CHECK(cloud.sigma.has_value());
  LONGS_EQUAL(16, cloud.sigma->size());
  DOUBLES_EQUAL(std::sqrt(16.0 + 1.0 / 12.0) * 1e-3, cloud.sigma->front(), 1e-12);
  STRCMP_CONTAINS("repeatability", cloud.sigma_from.c_str());
}

// A scan without one keeps its points' uncertainty open (the fit estimates the noise instead).
TEST(ScanFile, AScanWithoutARepeatabilityGivesNoSigma) {
  write_three_batches();
  const std::string named = path + ".scan";
  std::rename(path.c_str(), named.c_str());
  const dg::host::PointCloud cloud = dg::host::read_points(named);
  std::remove(named.c_str());
  CHECK_FALSE(cloud.sigma.has_value());
}

// A scan file is never replaced by a new writer.
TEST(ScanFile, ANewWriterNeverReplacesAnExistingFile) {
  write_three_batches();
  CHECK_THROWS(dg::host::ScanFileError, dg::host::ScanFileWriter(path));
  CHECK_THROWS(dg::host::ScanFileError, dg::host::ScanFileWriter::when_accepted(path, false));
  LONGS_EQUAL(37, dg::host::read_scan_file(path).points.size());
}

namespace {

digitizer_Envelope request_message(uint32_t scan_id) {
  digitizer_Envelope m = digitizer_Envelope_init_zero;
  m.which_body = digitizer_Envelope_scan_request_tag;
  m.body.scan_request.scan_id = scan_id;
  return m;
}

digitizer_Envelope done_message(uint32_t scan_id, uint64_t duration_us) {
  digitizer_Envelope m = digitizer_Envelope_init_zero;
  m.which_body = digitizer_Envelope_scan_done_tag;
  m.body.scan_done.scan_id = scan_id;
  m.body.scan_done.duration_us = duration_us;
  return m;
}

// A batch of `count` points on row y_mm from x0_mm at step_mm, numbered from first_seq, line 0.
digitizer_Envelope row_message(uint32_t first_seq, uint32_t count, double y_mm, double x0_mm, double step_mm) {
  digitizer_Envelope m = digitizer_Envelope_init_zero;
  m.which_body = digitizer_Envelope_points_tag;
  dg::point_batch_begin(&m.body.points, first_seq, 0);
  for (uint32_t i = 0; i < count; ++i) {
    dg::PointSample p;
    p.seq = first_seq + i;
    p.x_nm = static_cast<int32_t>(std::lround((x0_mm + i * step_mm) * 1e6));
    p.y_nm = static_cast<int32_t>(std::lround(y_mm * 1e6));
    p.z_nm = 1000;
    CHECK(dg::point_batch_append(&m.body.points, p) == dg::Status::kOk);
  }
  return m;
}

}  // namespace

TEST(ScanFile, AnAdaptiveScansPassesReadBackAsRows) {
  {
    dg::host::ScanFileWriter writer(path);
    digitizer_Envelope hello = digitizer_Envelope_init_zero;
    hello.which_body = digitizer_Envelope_hello_tag;
    writer.append(hello);
    writer.append(request_message(1));
    writer.append(row_message(1, 3, 0, 0, 2));  // the coarse grid: rows y = 0 and 2, x = 0, 2, 4
    writer.append(row_message(4, 3, 2, 0, 2));
    writer.append(done_message(1, 5000000));
    writer.append(request_message(2));  // a new row at y = 1
    writer.append(row_message(1, 3, 1, 0, 2));  // numbered afresh: the device restarted meanwhile
    writer.append(done_message(2, 2000000));
    writer.append(request_message(3));  // refused by the device: a request and nothing else
    writer.append(request_message(4));  // a new column at x = 1
    writer.append(row_message(4, 1, 0, 1, 1));
    writer.append(done_message(4, 1000000));
  }
  const dg::host::ScanData data = dg::host::read_scan_file(path);
  LONGS_EQUAL(3, data.passes.size());  // the refused one is gone
  LONGS_EQUAL(1, data.request->scan_id);
  LONGS_EQUAL(4, data.passes.back().scan_id);
  LONGS_EQUAL(10, data.points.size());
  LONGS_EQUAL(0, data.warnings.size());
  CHECK(data.done.has_value());
  LONGS_EQUAL(8000000, data.device_time_us);
  // Rows in y, each in x, a line each, its ends flagged.
  const int32_t expect[10][2] = {{0, 0}, {1, 0}, {2, 0}, {4, 0}, {0, 1}, {2, 1}, {4, 1}, {0, 2}, {2, 2}, {4, 2}};
  for (size_t k = 0; k < 10; ++k) {
    LONGS_EQUAL(expect[k][0] * 1000000, data.points[k].x_nm);
    LONGS_EQUAL(expect[k][1] * 1000000, data.points[k].y_nm);
    LONGS_EQUAL(static_cast<uint32_t>(expect[k][1]), data.points[k].line);
  }
  CHECK(data.points[0].flags & digitizer_PointFlag_POINT_LINE_START);
  CHECK(data.points[3].flags & digitizer_PointFlag_POINT_LINE_END);
  CHECK_FALSE(data.points[1].flags & (digitizer_PointFlag_POINT_LINE_START | digitizer_PointFlag_POINT_LINE_END));
  // As stored, for resuming: the last pass's points are the last ones.
  const dg::host::ScanData stored = dg::host::read_scan_file(path, dg::host::ScanOrder::kAsStored);
  LONGS_EQUAL(9, stored.last_pass_first_point);
  LONGS_EQUAL(1000000, stored.points.back().x_nm);
}

TEST(ScanFile, AnAdaptiveScanWhoseLastPassWasRefusedEndedWithThePassBefore) {
  {
    dg::host::ScanFileWriter writer(path);
    writer.append(request_message(1));
    writer.append(row_message(1, 3, 0, 0, 2));
    writer.append(done_message(1, 5000000));
    writer.append(request_message(2));  // refused: nothing follows
  }
  const dg::host::ScanData data = dg::host::read_scan_file(path);
  LONGS_EQUAL(1, data.passes.size());
  CHECK(data.done.has_value());
  LONGS_EQUAL(1, data.done->scan_id);
  LONGS_EQUAL(3, data.points.size());
}

TEST(ScanFile, RefusesASecondRequestInTheMiddleOfAPass) {
  {
    dg::host::ScanFileWriter writer(path);
    writer.append(request_message(1));
    writer.append(row_message(1, 3, 0, 0, 2));
    writer.append(request_message(2));
  }
  try {
    dg::host::read_scan_file(path);
    FAIL("a request in the middle of a pass was read");
  } catch (const dg::host::ScanFileError& e) {
    STRCMP_CONTAINS("two scan files joined", e.what());
  }
}

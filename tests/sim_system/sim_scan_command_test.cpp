// The scan command's own checks of its grid, before the simulated table moves: a step longer than
// its range is refused by name and leaves no file; a range of one position takes any step.
#include <CppUTest/TestHarness.h>

#include <unistd.h>

#include <stdexcept>
#include <string>

#include "host/cli/scan_command.h"
#include "host/scan/scan_file.h"

namespace {

std::string temp_path(const std::string& name) {
  return std::string(P_tmpdir) + "/dg_scan_command_" + std::to_string(getpid()) + "_" + name;
}

dg::host::ScanArgs dome_scan(const std::string& path) {
  dg::host::ScanArgs a;
  a.device = "sim:part=dome";
  a.output = path;
  a.quiet = true;
  return a;
}

}  // namespace

TEST_GROUP(SimScanCommand){};

TEST(SimScanCommand, RefusesAStepLongerThanItsRangeAndWritesNothing) {
  const std::string path = temp_path("long_step.scan");
  dg::host::ScanArgs a = dome_scan(path);
  a.x = "0:2";
  a.y = "0:10";
  a.step_mm = 5;
  try {
    dg::host::run_scan(a);
    FAIL("a 5 mm step over 2 mm was scanned");
  } catch (const std::invalid_argument& e) {
    STRCMP_CONTAINS("--step 5 mm is longer than the --x range 0:2 (2 mm)", e.what());
  }
  a.x = "0:10";
  a.step_mm = 1;
  a.step_y_mm = 20;
  try {
    dg::host::run_scan(a);
    FAIL("a 20 mm line step over 10 mm was scanned");
  } catch (const std::invalid_argument& e) {
    STRCMP_CONTAINS("--step-y 20 mm is longer than the --y range 0:10 (10 mm): the scan would measure one line", e.what());
  }
  CHECK(access(path.c_str(), F_OK) != 0);
}

TEST(SimScanCommand, ARangeOfOnePositionTakesAnyStep) {
  const std::string path = temp_path("one_line.scan");
  dg::host::ScanArgs a = dome_scan(path);
  a.x = "0:4";
  a.y = "10:10";
  a.step_mm = 1;
  a.step_y_mm = 5;
  LONGS_EQUAL(0, dg::host::run_scan(a));
  LONGS_EQUAL(5, dg::host::read_scan_file(path).points.size());
  std::remove(path.c_str());
}

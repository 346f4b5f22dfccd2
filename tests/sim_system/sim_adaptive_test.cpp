// An adaptive scan through the whole system: the scan command's coarse grid and rounds of passes
// on the simulated canister, one scan file of many passes read back as rows, and the fit of its
// points held to the tolerance against the canister's true shape (the oracle), with fewer points
// than the uniform grid whose fit keeps the same tolerance.
#include <CppUTest/TestHarness.h>

#include <unistd.h>

#include <cstdio>
#include <string>

#include "host/cli/scan_command.h"
#include "host/fit/one_surface_fit.h"
#include "host/scan/point_reader.h"
#include "host/scan/scan_file.h"
#include "tests/support/part_scan.h"

namespace {

std::string temp_path(const std::string& name) {
  return std::string(P_tmpdir) + "/dg_adaptive_" + std::to_string(getpid()) + "_" + name;
}

dg::host::ScanArgs canister_scan(const std::string& path, double step_mm) {
  dg::host::ScanArgs a;
  a.device = "sim:part=canister,noise_um=1,seed=5";
  a.step_mm = step_mm;
  a.output = path;
  a.quiet = true;
  return a;
}

}  // namespace

TEST_GROUP(SimAdaptive){};

TEST(SimAdaptive, TheCanisterToTenMicrometresWithLessThanHalfTheUniformGridsPoints) {
  const std::string path = temp_path("canister.scan");
  dg::host::ScanArgs a = canister_scan(path, 2);
  a.adaptive = true;
  a.tolerance_mm = 0.01;
  LONGS_EQUAL(0, dg::host::run_scan(a));
  const dg::host::ScanData data = dg::host::read_scan_file(path);
  CHECK(data.passes.size() > 1);
  CHECK(data.done.has_value());
  const dg::host::PointCloud cloud = dg::host::read_points(path);
  std::remove(path.c_str());
  dg::host::Parameters params;
  dg::host::Creases creases;
  const dg::host::ToleranceResult fit = dg::host::fit_one_surface(cloud, 0.01, &params, &creases);
  CHECK_TEXT(fit.kept && fit.validation.passed, fit.reason.c_str());
  // The oracle: the surface against the canister's true shape between every sample.
  dg::test::PartScan truth;
  truth.kind = dg::sim::PartKind::kCanister;
  const double off_mm = dg::test::max_error_against_part(fit.surface, truth);
  std::printf("\n  adaptive: %zu points in %zu passes; its fit is within %.4f mm of the true canister\n", cloud.points.size(),
              data.passes.size(), off_mm);
  CHECK(off_mm <= 0.01);

  // The uniform grid whose fit keeps 0.01 mm: 1 mm (2 mm's is refused between the samples).
  const std::string uniform_path = temp_path("uniform.scan");
  LONGS_EQUAL(0, dg::host::run_scan(canister_scan(uniform_path, 1)));
  const dg::host::PointCloud uniform = dg::host::read_points(uniform_path);
  std::remove(uniform_path.c_str());
  const dg::host::ToleranceResult uniform_fit = dg::host::fit_one_surface(uniform, 0.01, &params, &creases);
  CHECK(uniform_fit.kept && uniform_fit.validation.passed);
  CHECK(cloud.points.size() * 2 < uniform.points.size());
}

TEST(SimAdaptive, RefusesWhatItCannotRefine) {
  dg::host::ScanArgs a = canister_scan(temp_path("refused.scan"), 2);
  a.adaptive = true;
  CHECK_THROWS(std::invalid_argument, dg::host::run_scan(a));  // no tolerance
  a.tolerance_mm = 0.01;
  a.step_y_mm = 1;
  CHECK_THROWS(std::invalid_argument, dg::host::run_scan(a));  // unequal steps
  a.step_y_mm = 0;
  a.mode = "fly";
  CHECK_THROWS(std::invalid_argument, dg::host::run_scan(a));
}

TEST(SimAdaptive, ResumingAFinishedAdaptiveScanRefinesItToATighterTolerance) {
  const std::string path = temp_path("resumed.scan");
  dg::host::ScanArgs a = canister_scan(path, 2);
  a.adaptive = true;
  a.tolerance_mm = 0.05;
  LONGS_EQUAL(0, dg::host::run_scan(a));
  const size_t loose = dg::host::read_scan_file(path).points.size();
  a.resume = true;
  a.tolerance_mm = 0.01;
  LONGS_EQUAL(0, dg::host::run_scan(a));
  const dg::host::ScanData data = dg::host::read_scan_file(path);
  std::remove(path.c_str());
  CHECK(data.points.size() > loose);
  CHECK(data.passes.size() > 1);
}

// fit on a large scattered cloud, which it fits in a spatial order: the same surface as in the
// file's order, and a refusal that names the file's point.
#include "host/cli/fit_command.h"

#include <CppUTest/TestHarness.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "host/fit/bspline_fit.h"
#include "host/fit/orthogonal_distances.h"
#include "host/scan/point_export.h"
#include "host/scan/point_reader.h"
#include "host/scan/spatial_order.h"
#include "tests/support/scattered_cloud.h"
#include "tests/support/standard_output.h"

using namespace dg::host;

namespace {

double height(double x, double y) { return 2 + 0.01 * x + 0.3 * std::sin(x / 7) * std::cos(y / 9); }

}  // namespace

TEST_GROUP(FitCommand) {
  std::string base;
  void setup() override { base = std::string(P_tmpdir) + "/dg_fit_" + std::to_string(getpid()); }
  void teardown() override {
    for (const char* suffix : {".csv", ".json", ".err"}) std::remove((base + suffix).c_str());
  }
};

TEST(FitCommand, ALargeScatteredCloudGivesTheSurfaceItsFileOrderGives) {
  const PointCloud made = dg::test::scattered_cloud(kSpatialOrderFrom, 40.0, 30.0, 3, 0.002, height);
  write_cloud_csv(base + ".csv", made.points, nullptr);
  FitArgs a;
  a.input = base + ".csv";
  a.output = base + ".json";
  a.ctrl = "12x12";
  a.no_creases = true;
  a.quiet = true;
  LONGS_EQUAL(0, run_fit(a));
  std::ifstream in(a.output);
  const nlohmann::json j = nlohmann::json::parse(in);
  // The oracle: the same fit of the points as the file holds them, which is not in a spatial order.
  const PointCloud file = read_points(a.input);
  const Parameters params = parameterize(file, Parameterization::kTableXy);
  LsqSpec spec;
  spec.knots_u = spec.knots_v = clamped_uniform_knots(12, 3);
  const BSplineSurface s = fit_least_squares(file.points, params, nullptr, spec);
  double largest = 0, sum_sq = 0;
  for (double d : orthogonal_distances(s, file.points, params)) {
    largest = std::fmax(largest, std::fabs(d)), sum_sq += d * d;
  }
  DOUBLES_EQUAL(largest, j["fit"]["distance"]["max_abs"].get<double>(), 1e-9);
  const double rms = std::sqrt(sum_sq / static_cast<double>(file.points.size()));
  DOUBLES_EQUAL(rms, j["fit"]["distance"]["rms"].get<double>(), 1e-12);
  const std::vector<double> control = j["control_points"][0].get<std::vector<double>>();
  DOUBLES_EQUAL(s.control[0].z, control[2], 1e-9);
}

TEST(FitCommand, ARefusalNamesThePointByItsRowInTheFile) {
  // One reading 1 mm high among 100,000 scattered points with 2 um of noise: 0.02 mm cannot be kept,
  // and the refusal names that reading by its place in the file, which the spatial order moved.
  PointCloud made = dg::test::scattered_cloud(kSpatialOrderFrom, 40.0, 30.0, 5, 0.002, height);
  const size_t spike = 12345;
  made.points[spike].z += 1.0;
  const std::vector<uint32_t> order = spatial_order(made.points);
  CHECK(std::find(order.begin(), order.end(), spike) - order.begin() != static_cast<std::ptrdiff_t>(spike));
  write_cloud_csv(base + ".csv", made.points, nullptr);
  FitArgs a;
  a.input = base + ".csv";
  a.output = base + ".json";
  a.tolerance_mm = 0.02;
  a.no_regions = true;
  a.quiet = true;
  int status = -1;
  const std::string said = dg::test::printed_by([&] { return run_fit(a); }, base + ".err", status, 2);
  LONGS_EQUAL(kExitToleranceRefused, status);
  const PointCloud file = read_points(a.input);
  char where[96];
  std::snprintf(where, sizeof where, "at point %zu (%.3f, %.3f, %.3f)", spike + 1, file.points[spike].x,
                file.points[spike].y, file.points[spike].z);
  CHECK_TEXT(said.find(where) != std::string::npos, said.c_str());
}

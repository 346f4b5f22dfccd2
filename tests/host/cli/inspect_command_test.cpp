// inspect --align through the command: a scan larger than its nominal (an open mesh of part of the
// part) is aligned by its points over the mesh, and the command says how many lay beyond its edge.
#include "host/cli/inspect_command.h"

#include <CppUTest/TestHarness.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/cad/mesh_writer.h"
#include "host/geometry/vec3.h"
#include "host/scan/point_export.h"
#include "hw/sim/parts.h"
#include "tests/support/part_mesh.h"
#include "tests/support/standard_output.h"

using namespace dg::host;

namespace {

// The canister's true shape read over [x0, x1] x [y0, y1], every `step` mm.
std::vector<Point3> canister(double x0, double x1, double y0, double y1, double step) {
  std::vector<Point3> points;
  for (double y = y0; y <= y1 + 1e-9; y += step)
    for (double x = x0; x <= x1 + 1e-9; x += step) points.push_back({x, y, dg::sim::shape_height_mm(dg::sim::PartKind::kCanister, x, y)});
  return points;
}

// What run_inspect(a) prints on standard output, and its exit status.
std::string inspect_output(const InspectArgs& a, const std::string& capture, int& status) {
  return dg::test::printed_by([&] { return run_inspect(a); }, capture, status);
}

}  // namespace

TEST_GROUP(InspectCommand) {
  std::string base;
  void setup() override { base = std::string(P_tmpdir) + "/dg_inspect_" + std::to_string(getpid()); }
  void teardown() override {
    for (const char* suffix : {".csv", ".stl"}) std::remove((base + suffix).c_str());
  }
};

TEST(InspectCommand, AScanLargerThanItsNominalIsAlignedByItsPointsOverIt) {
  // The dish of the canister meshed over 24 x 18 mm; the scan, 40 x 30 mm, shifted by (0.3, -0.2,
  // 0.05) mm. Its points beyond the mesh's border measured their distance to the border and pulled
  // the part: the alignment did not converge and left the points over the mesh 0.3 mm off.
  write_mesh(base + ".stl", dg::test::part_mesh(dg::sim::PartKind::kCanister, 8, 32, 6, 24));
  std::vector<Point3> scan = canister(0, 40, 0, 30, 1);
  for (Point3& p : scan) p = p + Point3{0.3, -0.2, 0.05};
  write_cloud_csv(base + ".csv", scan, nullptr);
  InspectArgs a;
  a.points = base + ".csv";
  a.surface = base + ".stl";
  a.align = true;
  a.json = true;
  int status = -1;
  const nlohmann::json j = nlohmann::json::parse(inspect_output(a, base + ".out", status));
  LONGS_EQUAL(0, status);
  CHECK(j["alignment"]["converged"].get<bool>());
  CHECK(j["alignment"]["points_beyond_edge"].get<int>() > 500);
  CHECK(j["deviation"]["rms"].get<double>() < 0.001);
  DOUBLES_EQUAL(-0.3, j["alignment"]["translation_mm"][0].get<double>(), 0.005);
  a.json = false;
  const std::string text = inspect_output(a, base + ".out", status);
  STRCMP_CONTAINS("beyond the nominal's edge (their distance is to the edge, not along a normal)", text.c_str());
}

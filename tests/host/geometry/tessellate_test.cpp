// Tessellation to a chord tolerance, and the mesh files: our PLY reader reads the mesh's vertices.
#include "host/geometry/tessellate.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <cstdio>
#include <unistd.h>

#include "host/scan/ply_reader.h"
#include "host/cad/mesh_writer.h"
#include "host/geometry/vec3.h"
#include "tests/support/sample_surfaces.h"

using namespace dg::host;

namespace {

double distance_to_mesh(const Point3& p, const Mesh& mesh) {
  double best = HUGE_VAL;
  for (const auto& t : mesh.triangles) {
    best = std::fmin(best, distance_to_triangle(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]));
  }
  return best;
}

}  // namespace

TEST_GROUP(Tessellate){};

TEST(Tessellate, KeepsTheChordToleranceAndRefinesWhereItMust) {
  const BSplineSurface s = dg::test::clamped_sample();
  const Mesh coarse = tessellate(s, 0.1);
  const Mesh fine = tessellate(s, 0.01);
  CHECK(coarse.chord_error_mm <= 0.1);
  CHECK(fine.chord_error_mm <= 0.01);
  CHECK(fine.triangles.size() > coarse.triangles.size());
  // Surface points away from the check points are within the tolerance too (sampled; the check
  // points are where the error of a smooth surface peaks, so allow a tenth more).
  double worst = 0;
  for (int a = 1; a < 10; ++a)
    for (int b = 1; b < 10; ++b) worst = std::fmax(worst, distance_to_mesh(s.evaluate(a / 10.3, b / 9.7), coarse));
  CHECK(worst < 0.11);
}

TEST(Tessellate, RefusesANonPositiveChordAndAnEndlessMesh) {
  CHECK_THROWS(std::invalid_argument, tessellate(dg::test::clamped_sample(), 0.0));
  CHECK_THROWS(std::invalid_argument, tessellate(dg::test::clamped_sample(), 1e-9, 1000));
}

TEST(Tessellate, MeshFilesHoldEveryVertexAndTriangle) {
  const Mesh mesh = tessellate(dg::test::clamped_sample(), 0.05);
  const std::string stl = stl_bytes(mesh);
  LONGS_EQUAL(84 + 50 * mesh.triangles.size(), stl.size());
  const std::string ply = ply_mesh_bytes(mesh);
  const PointCloud back = parse_ply_points(reinterpret_cast<const uint8_t*>(ply.data()), ply.size(), "mesh.ply");
  LONGS_EQUAL(mesh.vertices.size(), back.points.size());
  DOUBLES_EQUAL(mesh.vertices.back().z, back.points.back().z, 1e-5);
  const std::string obj = obj_text(mesh);
  STRCMP_CONTAINS("f 1 ", obj.c_str());
  CHECK_THROWS(std::invalid_argument, write_mesh("mesh.dxf", mesh));
}

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

TEST(Tessellate, LinesGatherWhereTheSurfaceBendsAndTheChordHoldsBetweenThem) {
  // Flat over u < 0.5, a bump over u > 0.5: a 9 x 4 cubic net whose heights rise only on the right.
  BSplineSurface s;
  s.degree_u = s.degree_v = 3;
  s.count_u = 9, s.count_v = 4;
  s.knots_u = clamped_uniform_knots(9, 3);
  s.knots_v = clamped_uniform_knots(4, 3);
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 4; ++j) s.control.push_back({i * 5.0, j * 10.0, i >= 6 ? (i == 7 ? 6.0 : 2.0) : 0.0});
  const Mesh mesh = tessellate(s, 0.002);
  // The grid's u lines are the vertices' distinct x along the first v line.
  size_t left = 0, right = 0;
  for (size_t k = 0; k < mesh.vertices.size(); ++k) {
    if (mesh.vertices[k].y != mesh.vertices[0].y) continue;
    (mesh.vertices[k].x < 20 ? left : right) += 1;
  }
  CHECK(right > 4 * left);
  // The surface itself, densely and away from the check points, is within the tolerance (a tenth
  // allowed for the check points' being where a smooth surface's error peaks).
  double worst = 0;
  for (int a = 0; a <= 40; ++a)
    for (int b = 0; b <= 10; ++b) worst = std::fmax(worst, distance_to_mesh(s.evaluate(a / 40.0, b / 10.0), mesh));
  CHECK(worst < 0.0022);
}

TEST(Tessellate, AnAngleToleranceKeepsEveryTriangleNearTheSurfacesNormal) {
  const BSplineSurface s = dg::test::clamped_sample();
  const Mesh loose = tessellate(s, 0.5), tight = tessellate(s, 0.5, kMaxMeshTriangles, 3.0);
  CHECK(tight.triangles.size() > loose.triangles.size());
  double worst_deg = 0;
  for (const auto& t : tight.triangles) {
    const Point3 &a = tight.vertices[t[0]], &b = tight.vertices[t[1]], &c = tight.vertices[t[2]];
    const Point3 n = cross(b - a, c - a);
    // The surface's normal where the triangle's centroid lies, found as the closest of a fine sampling.
    const Point3 centroid = (1.0 / 3) * (a + b + c);
    double best = HUGE_VAL, best_u = 0, best_v = 0;
    for (int p = 0; p <= 200; ++p)
      for (int q = 0; q <= 200; ++q) {
        const double d = norm(s.evaluate(p / 200.0, q / 200.0) - centroid);
        if (d < best) best = d, best_u = p / 200.0, best_v = q / 200.0;
      }
    Point3 point, su, sv;
    s.evaluate(best_u, best_v, point, su, sv);
    const Point3 m = cross(su, sv);
    worst_deg = std::fmax(worst_deg, std::acos(std::fmin(1.0, dot(n, m) / (norm(n) * norm(m)))) * 180 / M_PI);
  }
  CHECK(worst_deg < 4.0);
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

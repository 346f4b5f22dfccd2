// Trimmed faces meshed to their trims: a disc and the plate with the disc's hole cover the plate
// exactly, neither overlapping nor leaving a gap, with the loops' exact areas as the oracle.
#include "host/geometry/face_mesh.h"

#include <CppUTest/TestHarness.h>

#include <cmath>

#include "host/geometry/tessellate.h"
#include "tests/support/sample_surfaces.h"

using namespace dg::host;

namespace {

// The loop's area (counter-clockwise positive).
double loop_area(const TrimLoop& loop) { return 0.5 * twice_signed_area(loop); }

// The triangles' area seen from above (positive for counter-clockwise in XY), and the least of them.
double projected_area(const Mesh& mesh, double* smallest_signed) {
  double total = 0;
  *smallest_signed = HUGE_VAL;
  for (const auto& t : mesh.triangles) {
    const Point3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const double area = 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
    total += area;
    *smallest_signed = std::fmin(*smallest_signed, area);
  }
  return total;
}

// A 40 x 30 mm tilted plane with a disc of radius `r` (n corners) at (20.3, 14.7), and the plate
// around it with the disc as its hole.
std::vector<TrimmedFace> disc_and_plate(double r, int n) {
  const BSplineSurface plane = dg::test::tilted_plane();
  TrimmedFace disc, plate;
  disc.surface = plate.surface = plane;
  TrimLoop circle;
  for (int k = 0; k < n; ++k) {
    const double angle = 2 * M_PI * k / n;
    circle.push_back({20.3 + r * std::cos(angle), 14.7 + r * std::sin(angle)});
  }
  disc.loops = {circle};
  const Point3 &low = plane.at(0, 0), &high = plane.at(plane.count_u - 1, plane.count_v - 1);
  TrimLoop hole(circle.rbegin(), circle.rend());
  plate.loops = {{{low.x, low.y}, {high.x, low.y}, {high.x, high.y}, {low.x, high.y}}, hole};
  return {disc, plate};
}

}  // namespace

TEST_GROUP(FaceMesh){};

TEST(FaceMesh, ADiscAndThePlateAroundItCoverThePlateExactly) {
  const std::vector<TrimmedFace> faces = disc_and_plate(8.0, 97);
  const Mesh disc = tessellate_faces({faces[0]}, 0.01, 1.0);
  const Mesh plate = tessellate_faces({faces[1]}, 0.01, 1.0);
  double least_disc = 0, least_plate = 0;
  const double disc_area = projected_area(disc, &least_disc);
  const double plate_area = projected_area(plate, &least_plate);
  const double circle = loop_area(faces[0].loops[0]);
  const double rectangle = loop_area(faces[1].loops[0]);
  // Every triangle wound one way (none folded over), and the areas those of the loops: the mesh
  // stops on the trim, with no triangle over it and no gap before it.
  CHECK(least_disc > 0);
  CHECK(least_plate > 0);
  DOUBLES_EQUAL(circle, disc_area, 1e-9 * rectangle);
  DOUBLES_EQUAL(rectangle - circle, plate_area, 1e-9 * rectangle);
  // The vertices on the trim lie on the surface, not on a chord of the grid.
  for (const Point3& v : disc.vertices) {
    const Point3 on = point_above(faces[0].surface, v.x, v.y);
    DOUBLES_EQUAL(on.z, v.z, 1e-9);
  }
}

TEST(FaceMesh, CornersOfTheLoopInsideATriangleBecomeVertices) {
  // A coarse grid (5 mm cells, no refinement on a plane) and a fine loop (a 3.1 mm disc of 40
  // corners): several corners fall inside one triangle, and the cut follows each of them.
  const std::vector<TrimmedFace> faces = disc_and_plate(3.1, 40);
  const Mesh disc = tessellate_faces({faces[0]}, 1.0, 5.0);
  const Mesh plate = tessellate_faces({faces[1]}, 1.0, 5.0);
  double least = 0, least_plate = 0;
  const double circle = loop_area(faces[0].loops[0]);
  DOUBLES_EQUAL(circle, projected_area(disc, &least), 1e-9 * circle);
  DOUBLES_EQUAL(1200 - circle, projected_area(plate, &least_plate), 1e-9 * 1200);
  CHECK(least > 0);
  CHECK(least_plate > 0);
  CHECK(disc.vertices.size() > 40);  // every corner of the loop is a vertex
}

TEST(FaceMesh, RegionsThatMeetTheScansEdgeCoverItToo) {
  // A half disc on the scan's left edge (a region of the part that runs off the scanned area) and
  // the rest of the plate: each loop meets the edge of the surface's domain at two corners.
  const BSplineSurface plane = dg::test::tilted_plane();
  TrimLoop half, rest;
  const int n = 37;
  for (int k = 0; k <= n; ++k) {
    const double angle = -M_PI / 2 + M_PI * k / n;
    half.push_back({6.3 * std::cos(angle), 14.6 + 6.3 * std::sin(angle)});
  }
  rest = {{0, 0}, {40, 0}, {40, 30}, {0, 30}};
  rest.insert(rest.end(), half.rbegin(), half.rend());
  TrimmedFace a, b;
  a.surface = b.surface = plane;
  a.loops = {half};
  b.loops = {rest};
  double least_a = 0, least_b = 0;
  const Mesh mesh_a = tessellate_faces({a}, 0.01, 0.5), mesh_b = tessellate_faces({b}, 0.01, 0.5);
  const double area_a = projected_area(mesh_a, &least_a), area_b = projected_area(mesh_b, &least_b);
  CHECK(least_a > 0);
  CHECK(least_b > 0);
  // Together exactly the plate; each within the loops' 0.1 um move of its loop's area.
  DOUBLES_EQUAL(1200, area_a + area_b, 1e-9 * 1200);
  DOUBLES_EQUAL(loop_area(half), area_a, 1e-4 * 2 * 6.3);
  DOUBLES_EQUAL(loop_area(rest), area_b, 1e-4 * 2 * 6.3);
}

// Closest points on triangles and meshes: against dense sampling of the triangle, against every
// triangle tried in turn, and signed distances to a cube whose true distances are known.
#include "host/geometry/triangle_mesh.h"

#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "host/geometry/vec3.h"

using namespace dg::host;

namespace {

// The cube [0, 10]^3 as 12 triangles, counter-clockwise seen from outside.
Mesh cube() {
  Mesh m;
  for (int k = 0; k < 8; ++k) m.vertices.push_back({10.0 * (k & 1), 10.0 * ((k >> 1) & 1), 10.0 * ((k >> 2) & 1)});
  const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

// The true signed distance to the cube [0, 10]^3: positive outside.
double cube_distance(const Point3& p) {
  const double dx = std::max({-p.x, p.x - 10, 0.0}), dy = std::max({-p.y, p.y - 10, 0.0}), dz = std::max({-p.z, p.z - 10, 0.0});
  const double outside = std::sqrt(dx * dx + dy * dy + dz * dz);
  if (outside > 0) return outside;
  return -std::min({p.x, 10 - p.x, p.y, 10 - p.y, p.z, 10 - p.z});
}

size_t locate(const Mesh& m) { return MeshLocator(m).triangle_count(); }

}  // namespace

TEST_GROUP(TriangleMesh){};

TEST(TriangleMesh, ClosestPointOnATriangleIsNoFartherThanAnySampleOfIt) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> any(-5.0, 5.0);
  for (int trial = 0; trial < 300; ++trial) {
    const Point3 a{any(rng), any(rng), any(rng)}, b{any(rng), any(rng), any(rng)}, c{any(rng), any(rng), any(rng)};
    const Point3 p{2 * any(rng), 2 * any(rng), 2 * any(rng)};
    int feature = -1;
    const double found = norm(p - closest_on_triangle(p, a, b, c, &feature));
    CHECK(feature >= 0 && feature <= 6);
    // The oracle: the nearest of 200 x 200 barycentric samples, which can be no nearer.
    double sampled = HUGE_VAL;
    constexpr int kSteps = 200;
    for (int i = 0; i <= kSteps; ++i) {
      for (int j = 0; i + j <= kSteps; ++j) {
        const double s = static_cast<double>(i) / kSteps, t = static_cast<double>(j) / kSteps;
        sampled = std::min(sampled, norm(p - (a + s * (b - a) + t * (c - a))));
      }
    }
    CHECK(found <= sampled + 1e-12);
    // A sample is at most half a step's diagonal from the true nearest point.
    const double step = std::max({norm(b - a), norm(c - a), norm(c - b)}) / kSteps;
    CHECK(sampled - found <= step);
  }
}

TEST(TriangleMesh, TheTreeFindsTheSameDistanceAsEveryTriangleTriedInTurn) {
  // A wavy sheet of 2 x 40 x 30 triangles and points above, below and beyond it.
  Mesh m;
  for (int j = 0; j <= 30; ++j)
    for (int i = 0; i <= 40; ++i) m.vertices.push_back({1.0 * i, 1.0 * j, std::sin(0.3 * i) * std::cos(0.2 * j)});
  for (uint32_t j = 0; j < 30; ++j)
    for (uint32_t i = 0; i < 40; ++i) {
      const uint32_t v = j * 41 + i;
      m.triangles.push_back({v, v + 1, v + 42});
      m.triangles.push_back({v, v + 42, v + 41});
    }
  const MeshLocator locator(m);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> x(-5, 45), y(-5, 35), z(-3, 3);
  for (int trial = 0; trial < 500; ++trial) {
    const Point3 p{x(rng), y(rng), z(rng)};
    double brute = HUGE_VAL;
    for (const auto& t : m.triangles) {
      int feature = 0;
      brute = std::min(brute, norm(p - closest_on_triangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], &feature)));
    }
    const Closest c = locator.closest(p);
    DOUBLES_EQUAL(brute, std::fabs(c.distance), 1e-12);
    DOUBLES_EQUAL(std::fabs(c.distance), norm(p - c.point), 1e-12);
  }
}

TEST(TriangleMesh, SignedDistancesToACubeAreTrueAtFacesEdgesAndCorners) {
  const MeshLocator locator(cube());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> any(-4, 14);
  int outside_near_edge_or_corner = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Point3 p{any(rng), any(rng), any(rng)};
    DOUBLES_EQUAL(cube_distance(p), locator.closest(p).distance, 1e-9);
    const int beyond = (p.x < 0 || p.x > 10) + (p.y < 0 || p.y > 10) + (p.z < 0 || p.z > 10);
    outside_near_edge_or_corner += beyond >= 2;
  }
  // Points whose nearest feature is an edge or a corner, where one face's normal can give the wrong side.
  CHECK(outside_near_edge_or_corner > 300);
}

// A closed solid has no border: no foot on the cube, at a face, an edge or a corner, is on one.
// An open mesh's border is its edges of one triangle and their corners: the square [0, 10]^2 as two
// triangles has its diagonal inside, shared, and its four sides and corners on the border.
TEST(TriangleMesh, AFootOnAnOpenMeshsBorderIsMarkedAndNoneOnAClosedOne) {
  const MeshLocator solid(cube());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> any(-4, 14);
  for (int trial = 0; trial < 500; ++trial) CHECK_FALSE(solid.closest({any(rng), any(rng), any(rng)}).on_border);
  Mesh square;
  square.vertices = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}};
  square.triangles = {{0, 1, 2}, {0, 2, 3}};
  const MeshLocator open(square);
  CHECK_FALSE(open.closest({3, 2, 1}).on_border);   // above the first triangle
  CHECK_FALSE(open.closest({5, 5, -1}).on_border);  // below the shared diagonal
  CHECK(open.closest({12, 5, 1}).on_border);        // beside the side x = 10
  CHECK(open.closest({5, -3, 0}).on_border);        // beside y = 0
  CHECK(open.closest({-2, 12, 0}).on_border);       // beyond the corner (0, 10)
  CHECK(open.closest({10.5, 5, 2}).on_border);      // above and a little beside the side: its foot on it
}

TEST(TriangleMesh, RefusesAMeshWithoutTrianglesOrWithAnIndexOutOfRange) {
  Mesh empty;
  CHECK_THROWS(std::invalid_argument, locate(empty));
  Mesh bad = cube();
  bad.triangles[3][1] = 8;
  CHECK_THROWS(std::invalid_argument, locate(bad));
  Mesh not_finite = cube();
  not_finite.vertices[2].z = NAN;
  CHECK_THROWS(std::invalid_argument, locate(not_finite));
}

TEST(TriangleMesh, TrianglesWithoutAreaAreCountedAndLeftOutOfTheSearch) {
  Mesh m = cube();
  m.vertices.push_back({5, 5, 10});
  m.triangles.push_back({4, 8, 7});  // 4 = (0,0,10), 8 = (5,5,10), 7 = (10,10,10): one line
  const MeshLocator locator(m);
  LONGS_EQUAL(1, locator.without_area());
  DOUBLES_EQUAL(2.0, locator.closest({5, 5, 12}).distance, 1e-12);
  DOUBLES_EQUAL(-3.0, locator.closest({5, 5, 7}).distance, 1e-12);
}

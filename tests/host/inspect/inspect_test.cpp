// Inspection against parts whose true distances are known: a plane and a sphere cap, points on
// both sides, far away, and beyond the edges; the bands count what Li and Zhang 2013, eq. 8 counts.
#include "host/inspect/inspect.h"

#include <CppUTest/TestHarness.h>

#include <stdexcept>

#include <cmath>
#include <random>

#include "host/fit/bspline_fit.h"
#include "host/geometry/surface_locator.h"
#include "host/geometry/triangle_mesh.h"
#include "host/geometry/vec3.h"
#include "tests/support/sample_surfaces.h"

using namespace dg::host;

namespace {

// A fitted sphere cap of radius 50 (centre (20, 15, -40)): bicubic 12 x 12, a few um from the sphere.
BSplineSurface sphere_cap() {
  PointCloud c;
  for (int j = 0; j <= 60; ++j)
    for (int i = 0; i <= 80; ++i) {
      const double x = 0.5 * i, y = 0.5 * j;
      c.points.push_back({x, y, -40 + std::sqrt(2500 - (x - 20) * (x - 20) - (y - 15) * (y - 15))});
    }
  LsqSpec spec;
  spec.knots_u = spec.knots_v = clamped_uniform_knots(12, 3);
  return fit_least_squares(c.points, parameterize(c, Parameterization::kTableXy), nullptr, spec);
}

// A corrugated sheet, z = 3 sin(x): bicubic 40 x 6 over 0..30 x 0..10 mm, where a start on the
// wrong flank of a ridge settles in a local minimum.
BSplineSurface corrugated() {
  PointCloud c;
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 300; ++i) c.points.push_back({0.1 * i, 0.5 * j, 3 * std::sin(0.1 * i)});
  LsqSpec spec;
  spec.knots_u = clamped_uniform_knots(40, 3);
  spec.knots_v = clamped_uniform_knots(6, 3);
  return fit_least_squares(c.points, parameterize(c, Parameterization::kTableXy), nullptr, spec);
}

}  // namespace

TEST_GROUP(Inspect){};

TEST(Inspect, PlaneDistancesAreExactWithTheirSign) {
  const BSplineSurface plane = dg::test::tilted_plane();
  const double n = std::sqrt(1 + 0.01);  // |(-0.1, 0, 1)|
  std::vector<Point3> points;
  std::vector<double> expected;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> x(5, 35), y(5, 25), off(-2, 2);
  for (int k = 0; k < 200; ++k) {
    const double px = x(rng), py = y(rng), h = off(rng);
    points.push_back({px, py, 1 + 0.1 * px + h});
    expected.push_back(h / n);
  }
  const Inspection r = inspect(points, plane, {0.5, 1.0});
  for (size_t k = 0; k < points.size(); ++k) DOUBLES_EQUAL(expected[k], r.points[k].distance, 1e-9);
  size_t within_half = 0;
  for (double e : expected) within_half += std::fabs(e) <= 0.5;
  LONGS_EQUAL(within_half, r.bands[0].count);
}

TEST(Inspect, SphereDistancesMatchTheTrueOnesFromAnyStart) {
  const BSplineSurface cap = sphere_cap();
  const SurfaceLocator locator(cap);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(0, 2 * M_PI), tilt(0, 0.3), radius(45, 56);
  for (int k = 0; k < 300; ++k) {
    const double a = angle(rng), t = tilt(rng), r = radius(rng);
    const Point3 p{20 + r * std::sin(t) * std::cos(a), 15 + r * std::sin(t) * std::sin(a), -40 + r * std::cos(t)};
    // Inside the cap's footprint the closest point is on the sphere: distance r - 50.
    const Point3 foot{20 + 50 * std::sin(t) * std::cos(a), 15 + 50 * std::sin(t) * std::sin(a), -40 + 50 * std::cos(t)};
    if (foot.x < 1 || foot.x > 39 || foot.y < 1 || foot.y > 29) continue;
    DOUBLES_EQUAL(r - 50, locator.closest(p).distance, 0.002);
  }
}

TEST(Inspect, PointsBeyondTheEdgeFindTheEdge) {
  const BSplineSurface plane = dg::test::tilted_plane();
  const Inspection r = inspect({{50, 15, 6}, {-10, -10, 1}, {20, 10, 3}}, plane, {});
  DOUBLES_EQUAL(norm(Point3{50, 15, 6} - Point3{40, 15, 5}), std::fabs(r.points[0].distance), 1e-9);
  DOUBLES_EQUAL(std::sqrt(200.0), std::fabs(r.points[1].distance), 1e-9);
  // Neither distance runs along a normal: both are marked and counted.
  CHECK(r.points[0].beyond_edge);
  CHECK(r.points[1].beyond_edge);
  LONGS_EQUAL(2, r.beyond_edge);
}

// The statistics and bands are of the points over the surface: a point 10 mm beyond the edge does
// not become the part's largest deviation, and the bands' shares count only the points over it.
TEST(Inspect, LeavesThePointsBeyondTheEdgeOutOfTheStatisticsAndBands) {
  const BSplineSurface plane = dg::test::tilted_plane();  // z = 1 + 0.1 x over 0..40 x 0..30
  const double n = std::sqrt(1 + 0.01);
  const Inspection r = inspect({{50, 15, 6}, {20, 10, 3 + 0.02 * n}, {10, 20, 2 - 0.01 * n}, {30, 5, 4 + 0.2 * n}}, plane, {0.05});
  LONGS_EQUAL(1, r.beyond_edge);
  LONGS_EQUAL(4, r.points.size());
  LONGS_EQUAL(3, r.stats.count);
  DOUBLES_EQUAL(0.2, r.stats.max, 1e-9);
  DOUBLES_EQUAL(-0.01, r.stats.min, 1e-9);
  DOUBLES_EQUAL(0.07, r.stats.mean, 1e-9);
  LONGS_EQUAL(2, r.bands[0].count);
  DOUBLES_EQUAL(2.0 / 3.0, r.bands[0].share, 1e-12);
}

// Against an open mesh nominal (a single face of a part) a point off to the side of its border is
// beyond its edge as on a fitted surface, and one above the border along the normal is not; a
// closed mesh has no border, so nothing is marked on it.
TEST(Inspect, PointsBeyondAnOpenMeshsBorderAreMarkedAndLeftOutOfTheStatistics) {
  Mesh square;
  square.vertices = {{0, 0, 1}, {40, 0, 1}, {40, 30, 1}, {0, 30, 1}};
  square.triangles = {{0, 1, 2}, {0, 2, 3}};
  const MeshLocator locator(square);
  const Inspection r = inspect_nominal({{20, 10, 1.02}, {10, 20, 0.99}, {40, 15, 3}, {45, 15, 1}, {-3, -4, 1.5}},
                                       [&](const Point3& p) { return locator.closest(p); }, {0.05});
  CHECK_FALSE(r.points[0].beyond_edge);
  CHECK_FALSE(r.points[1].beyond_edge);
  CHECK_FALSE(r.points[2].beyond_edge);  // above the border, along the normal: 2 mm off the part
  CHECK(r.points[3].beyond_edge);
  CHECK(r.points[4].beyond_edge);
  LONGS_EQUAL(2, r.beyond_edge);
  LONGS_EQUAL(3, r.stats.count);
  DOUBLES_EQUAL(2.0, r.stats.max, 1e-9);
  LONGS_EQUAL(2, r.bands[0].count);
}

// With every point beyond the edge there is no deviation to report: refused, saying so.
TEST(Inspect, RefusesPointsThatAllLieBeyondTheEdge) {
  try {
    inspect({{50, 15, 6}, {-10, -10, 1}}, dg::test::tilted_plane(), {});
    FAIL("points all beyond the edge were inspected");
  } catch (const std::invalid_argument& e) {
    STRCMP_CONTAINS("every one of the 2 points lies beyond the surface's edge", e.what());
  }
}

// Only a point off to the side of the edge is beyond it: not one above the edge along its normal,
// not one a fraction of a micrometre past it, and none inside.
TEST(Inspect, APointIsBeyondTheEdgeOnlyWhereItsDistanceLeavesTheNormalThere) {
  const BSplineSurface plane = dg::test::tilted_plane();  // z = 1 + 0.1 x over 0..40 x 0..30
  const double n = std::sqrt(1 + 0.01);
  const Point3 normal{-0.1 / n, 0, 1 / n};
  const Point3 edge{40, 15, 5};
  const Inspection r = inspect({edge + 2.0 * normal,                // above the edge, along its normal
                                edge - 3.0 * normal,                // below it
                                {40.0005, 15, 5.00005},             // half a micrometre past it
                                {40.01, 15, 5.001},                 // ten micrometres past it
                                {20, 10, 3 + 0.5}, {0.5, 29.5, 1}},  // inside
                               plane, {});
  CHECK_FALSE(r.points[0].beyond_edge);
  CHECK_FALSE(r.points[1].beyond_edge);
  DOUBLES_EQUAL(2.0, r.points[0].distance, 1e-9);
  CHECK_FALSE(r.points[2].beyond_edge);
  CHECK(r.points[3].beyond_edge);
  CHECK_FALSE(r.points[4].beyond_edge);
  CHECK_FALSE(r.points[5].beyond_edge);
  LONGS_EQUAL(1, r.beyond_edge);
}

// No statistics from nothing, and none from a point whose distance overflows: both refused, the
// second naming the point.
TEST(Inspect, RefusesNoPointsAndAPointWhoseDistanceIsNotFinite) {
  CHECK_THROWS(std::invalid_argument, inspect({}, dg::test::tilted_plane(), {}));
  try {
    inspect({{1, 1, 1}, {1e308, 0, 1}}, dg::test::tilted_plane(), {0.01});
    FAIL("a point at 1e308 was inspected");
  } catch (const std::invalid_argument& e) {
    STRCMP_CONTAINS("point 2", e.what());
  }
}

// The bucket search may stop at a point's own bucket when the nearest sample (and the ring for a
// second start) lies within it: its nearest sample is still the one a scan of every sample finds,
// for points on, near and far from the surfaces, inside and outside the samples' box.
TEST(Inspect, TheLocatorStartsFromTheNearestSampleAsAScanOfAllFindsIt) {
  for (const bool sheet : {false, true}) {
    const BSplineSurface surface = sheet ? corrugated() : sphere_cap();
    const SurfaceLocator locator(surface);
    const std::vector<SurfaceLocator::Sample>& samples = locator.samples();
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> x(-5, sheet ? 35 : 45), y(-5, sheet ? 15 : 35), off(-3, 3);
    std::normal_distribution<double> near(0, 0.01);
    for (int k = 0; k < 2000; ++k) {
      const double px = x(rng), py = y(rng);
      const double on = sheet ? 3 * std::sin(px) : -40 + std::sqrt(std::fmax(0, 2500 - (px - 20) * (px - 20) - (py - 15) * (py - 15)));
      const Point3 p{px, py, on + (k % 2 == 0 ? near(rng) : off(rng))};
      double nearest_d2 = HUGE_VAL;
      for (const SurfaceLocator::Sample& s : samples) nearest_d2 = std::fmin(nearest_d2, dot(s.point - p, s.point - p));
      const Point3 found = samples[locator.starts(p).nearest].point;
      DOUBLES_EQUAL(nearest_d2, dot(found - p, found - p), 1e-12);
    }
  }
}

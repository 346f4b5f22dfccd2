// Li and Zhang's (2013) experiments: a sphere, a cylinder and a truncated cone from points and normals, with
// the paper's error measure (eq. 7 over a 401 x 401 evaluation) printed next to its Table 2.
#include "host/fit/hermite_fit.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <random>

#include "host/fit/fit_error.h"
#include "host/geometry/vec3.h"

using namespace dg::host;

namespace {

// Mean over a 401 x 401 evaluation of the squared error `error(point)` (Li and Zhang 2013, eq. 7).
double eq7(const BSplineSurface& s, const std::function<double(Point3)>& error, double* max_abs) {
  double sum = 0;
  *max_abs = 0;
  for (int i = 0; i <= 400; ++i) {
    for (int j = 0; j <= 400; ++j) {
      const double u = s.u_min() + (s.u_max() - s.u_min()) * i / 400.0;
      const double v = s.v_min() + (s.v_max() - s.v_min()) * j / 400.0;
      const double e = error(s.evaluate(u, v));
      sum += e * e;
      if (std::fabs(e) > *max_abs) *max_abs = std::fabs(e);
    }
  }
  return sum / (401.0 * 401.0);
}

HermiteGrid sphere_grid() {
  HermiteGrid g;
  const double xs[4] = {-2, -1, 1, 2};
  g.rows = g.cols = 4;
  for (double y : xs) {
    for (double x : xs) {
      const Point3 p{x, y, std::sqrt(9 - x * x - y * y)};
      g.points.push_back(p);
      g.normals.push_back((1.0 / 3.0) * p);
    }
  }
  return g;
}

// Li and Zhang's (2013) experiments 2-3: x = t in {2, 3, 4, 5}, theta in 6 steps over [-pi/2, 3pi/2], radius
// 1 (cylinder) or t (cone).
HermiteGrid revolved_grid(bool cone) {
  HermiteGrid g;
  g.rows = 6;
  g.cols = 4;
  for (int k = 0; k < 6; ++k) {
    const double theta = -M_PI / 2 + 2 * M_PI * k / 5.0;
    for (int c = 0; c < 4; ++c) {
      const double t = 2 + c, r = cone ? t : 1.0;
      g.points.push_back({t, r * std::sin(theta), r * std::cos(theta)});
      g.normals.push_back(cone ? Point3{-1, std::sin(theta), std::cos(theta)} : Point3{0, std::sin(theta), std::cos(theta)});
    }
  }
  return g;
}

}  // namespace

TEST_GROUP(HermiteFit){};

TEST(HermiteFit, SplineDerivativesAreExactForACubic) {
  // f(t) = t^3 - 2 t^2 + t on unequal steps, exact end derivatives: a C2 cubic spline is f itself.
  const std::vector<double> t = {0, 0.5, 1.7, 2.0, 3.1};
  std::vector<Point3> f;
  for (double x : t) f.push_back({x * x * x - 2 * x * x + x, x, 0});
  auto df = [](double x) { return Point3{3 * x * x - 4 * x + 1, 1, 0}; };
  const std::vector<Point3> d = spline_derivatives(f, t, df(t.front()), df(t.back()));
  for (size_t k = 0; k < t.size(); ++k) {
    DOUBLES_EQUAL(df(t[k]).x, d[k].x, 1e-12);
    DOUBLES_EQUAL(1.0, d[k].y, 1e-12);
  }
}

TEST(HermiteFit, TangentsOfFourPointsMeetEveryNormal) {
  // Four points on a circle (Li and Zhang 2013, Fig. 1): six end-tangent components, four constraints.
  std::vector<Point3> p, n;
  std::vector<double> t;
  for (int k = 0; k < 4; ++k) {
    const double a = 0.4 * k;
    p.push_back({std::cos(a), std::sin(a), 0});
    n.push_back({std::cos(a), std::sin(a), 0.0});
    t.push_back(a);
  }
  const std::vector<Point3> d = constrained_tangents(p, n, t);
  for (int k = 0; k < 4; ++k) {
    DOUBLES_EQUAL(0.0, dot(d[k], n[k]), 1e-7);
    // And near the circle's own unit tangent (arc-length parameters).
    DOUBLES_EQUAL(-std::sin(0.4 * k), d[k].x, 0.01);
    DOUBLES_EQUAL(std::cos(0.4 * k), d[k].y, 0.01);
  }
}

TEST(HermiteFit, SphereOfExperimentOneIsAnOrderOfMagnitudeBetterThanTheTable) {
  const HermiteResult r = fit_hermite(sphere_grid());
  CHECK(r.normal_residual_max < 1e-6);
  double max_z = 0, max_radial = 0;
  const double e7 = eq7(r.surface, [](Point3 p) { return p.z - std::sqrt(std::fmax(0.0, 9 - p.x * p.x - p.y * p.y)); }, &max_z);
  const double radial = eq7(r.surface, [](Point3 p) { return norm(p) - 3; }, &max_radial);
  std::printf("\n  Li and Zhang 2013 sphere: eq. 7 %.6f (paper 0.1735), max |dz| %.4f, orthogonal rms %.5f max %.5f\n", e7, max_z,
              std::sqrt(radial), max_radial);
  CHECK(e7 < 0.1735 / 10);
  // Through every grid point exactly.
  const HermiteGrid g = sphere_grid();
  for (int row = 0; row < 4; ++row) {
    for (int c = 0; c < 4; ++c) {
      const Point3 s = r.surface.evaluate(r.u[c], r.v[row]);
      const Point3 p = g.points[static_cast<size_t>(row) * 4 + c];
      DOUBLES_EQUAL(0.0, norm(s - p), 1e-12);
    }
  }
}

TEST(HermiteFit, CylinderAndConeOfExperimentsTwoAndThree) {
  const double paper[2] = {0.0932, 0.1342};
  for (int cone = 0; cone < 2; ++cone) {
    const HermiteResult r = fit_hermite(revolved_grid(cone == 1));
    double max_abs = 0;
    // The radial deviation from the true surface, at the evaluated point's own x.
    const double e7 = eq7(r.surface, [cone](Point3 p) {
      return std::hypot(p.y, p.z) - (cone ? p.x : 1.0);
    }, &max_abs);
    std::printf("  Li and Zhang 2013 %s: eq. 7 (radial) %.6f (paper %.4f), max %.4f\n", cone ? "cone" : "cylinder", e7, paper[cone], max_abs);
    CHECK(e7 < paper[cone] / 10);
  }
}

TEST(HermiteFit, PatchesJoinWithOneTangentPlane) {
  const HermiteResult r = fit_hermite(sphere_grid());
  // Across the interior knot u = r.u[1] the surface's derivatives agree from both sides.
  Point3 s0, su0, sv0, s1, su1, sv1;
  const double u = r.u[1], v = 0.5 * (r.v[1] + r.v[2]);
  r.surface.evaluate(u - 1e-9, v, s0, su0, sv0);
  r.surface.evaluate(u + 1e-9, v, s1, su1, sv1);
  DOUBLES_EQUAL(0.0, norm(su0 - su1), 1e-6);
  DOUBLES_EQUAL(0.0, norm(sv0 - sv1), 1e-6);
}

TEST(HermiteFit, RefusesDegenerateGrids) {
  HermiteGrid small;
  small.rows = small.cols = 2;
  small.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  small.normals.assign(4, Point3{0, 0, 1});
  CHECK_THROWS(FitError, fit_hermite(small));
  HermiteGrid g = sphere_grid();
  g.normals[5] = Point3{0, 0, 0};
  std::string error;
  try {
    fit_hermite(g);
  } catch (const FitError& e) {
    error = e.what();
  }
  STRCMP_CONTAINS("row 1, point 1 has zero length", error.c_str());
}

TEST(HermiteFit, TakesTheGridFromAScanWithNormalsTurningSerpentineLines) {
  PointCloud cloud;
  cloud.line = std::vector<uint32_t>{};
  cloud.normal = std::vector<Point3>{};
  const HermiteGrid sphere = sphere_grid();
  for (int row = 0; row < 4; ++row) {
    for (int k = 0; k < 4; ++k) {
      const int c = row % 2 == 0 ? k : 3 - k;  // odd lines run backwards
      cloud.points.push_back(sphere.points[static_cast<size_t>(row) * 4 + c]);
      cloud.normal->push_back(sphere.normals[static_cast<size_t>(row) * 4 + c]);
      cloud.line->push_back(static_cast<uint32_t>(row));
    }
  }
  const HermiteGrid g = hermite_grid(cloud, "sphere.csv");
  LONGS_EQUAL(4, g.rows);
  LONGS_EQUAL(4, g.cols);
  for (size_t k = 0; k < g.points.size(); ++k) DOUBLES_EQUAL(0.0, norm(g.points[k] - sphere.points[k]), 0);
  // A short line, or no normals, is an error naming the file.
  cloud.points.pop_back();
  cloud.normal->pop_back();
  cloud.line->pop_back();
  std::string error;
  try {
    hermite_grid(cloud, "sphere.csv");
  } catch (const FitError& e) {
    error = e.what();
  }
  STRCMP_CONTAINS("sphere.csv: line 3 has 3 points", error.c_str());
  cloud.normal.reset();
  CHECK_THROWS(FitError, hermite_grid(cloud, "sphere.csv"));
}

TEST(HermiteFit, AClosedGridJoinsAtItsSeam) {
  // The cylinder's rows of theta end where they start: the surface closes with one tangent plane.
  const HermiteResult r = fit_hermite(revolved_grid(false));
  CHECK(r.closed_v);
  CHECK(!r.closed_u);
  Point3 s0, su0, sv0, s1, su1, sv1;
  const double u = 0.5 * (r.u[1] + r.u[2]);
  r.surface.evaluate(u, r.v.front(), s0, su0, sv0);
  r.surface.evaluate(u, r.v.back(), s1, su1, sv1);
  DOUBLES_EQUAL(0.0, norm(s0 - s1), 1e-12);
  DOUBLES_EQUAL(0.0, norm(sv0 - sv1), 1e-9);
  // Periodic derivatives of a closed polygon of a circle point along the circle.
  std::vector<Point3> f;
  std::vector<double> t;
  for (int k = 0; k <= 12; ++k) {
    const double a = 2 * M_PI * k / 12;
    f.push_back({std::cos(a), std::sin(a), 0});
    t.push_back(a);
  }
  const std::vector<Point3> d = periodic_derivatives(f, t);
  for (int k = 0; k <= 12; ++k) {
    const double a = 2 * M_PI * k / 12;
    DOUBLES_EQUAL(-std::sin(a), d[static_cast<size_t>(k)].x, 2e-3);
    DOUBLES_EQUAL(std::cos(a), d[static_cast<size_t>(k)].y, 2e-3);
  }
}

// Measured points carry noise; the normals may still be exact (from CAD, or a probe's own). On an
// 11 x 9 grid of a sphere of radius 50 mm at 2 mm, 2 um of noise in z must not swing the end
// tangents: between the points the surface stays within 10 um of the true sphere (the oracle).
// With every normal constraint weighted as exact, the surface was 74 um off near the grid's edge.
TEST(HermiteFit, NoisyPointsDoNotSwingTheEndTangents) {
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0.0, 0.002);
  HermiteGrid g;
  g.rows = 9;
  g.cols = 11;
  for (int j = 0; j < g.rows; ++j) {
    for (int i = 0; i < g.cols; ++i) {
      const double x = 2.0 * i - 10, y = 2.0 * j - 8, z = std::sqrt(2500 - x * x - y * y);
      g.points.push_back({x, y, z + noise(rng)});
      g.normals.push_back({x / 50, y / 50, z / 50});
    }
  }
  const BSplineSurface s = fit_hermite(g).surface;
  double worst = 0;
  for (int i = 0; i <= 200; ++i) {
    for (int j = 0; j <= 200; ++j) {
      const Point3 p = s.evaluate(s.u_min() + (s.u_max() - s.u_min()) * i / 200.0, s.v_min() + (s.v_max() - s.v_min()) * j / 200.0);
      worst = std::fmax(worst, std::fabs(norm(p) - 50));
    }
  }
  std::printf("\n  noisy sphere grid: %.4f mm from the true sphere at worst between the points", worst);
  CHECK(worst <= 0.010);
}

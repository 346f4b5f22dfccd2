// Superquadric recovery (Koivunen and Bajcsy 1992, section 5.5): certified values first (a sphere is e1 = e2 = 1
// with a1 = a2 = a3 = r), then the shape classes of its Fig. 8, and data without volume refused.
#include "host/fit/superquadric.h"

#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "host/fit/fit_error.h"
#include "host/geometry/vec3.h"

using namespace dg::host;

namespace {

// Points spread over the whole surface of `s` (a grid in latitude and longitude).
std::vector<Point3> sample(const Superquadric& s, int n = 40) {
  std::vector<Point3> p;
  for (int i = 1; i < n; ++i) {
    const double eta = -M_PI / 2 + M_PI * i / n;
    for (int j = 0; j < 2 * n; ++j) p.push_back(s.surface_point(eta, -M_PI + M_PI * j / n));
  }
  return p;
}

Superquadric rotated(double a1, double a2, double a3, double e1, double e2, Point3 c) {
  Superquadric s;
  s.a[0] = a1;
  s.a[1] = a2;
  s.a[2] = a3;
  s.e1 = e1;
  s.e2 = e2;
  s.center = c;
  // 30 degrees about x, then 20 about z.
  const double cx = std::cos(M_PI / 6), sx = std::sin(M_PI / 6), cz = std::cos(M_PI / 9), sz = std::sin(M_PI / 9);
  const double rx[3][3] = {{1, 0, 0}, {0, cx, -sx}, {0, sx, cx}};
  const double rz[3][3] = {{cz, -sz, 0}, {sz, cz, 0}, {0, 0, 1}};
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) {
      double v = 0;
      for (int k = 0; k < 3; ++k) v += rz[col][k] * rx[k][row];
      s.axes[row][col] = v;  // the object's axis `row` in table coordinates
    }
  }
  return s;
}

}  // namespace

TEST_GROUP(Superquadric){};

TEST(Superquadric, RecoversASphereExactly) {
  Superquadric sphere;
  sphere.a[0] = sphere.a[1] = sphere.a[2] = 5;
  sphere.center = {1, 2, 3};
  const SuperquadricFit fit = fit_superquadric(sample(sphere));
  std::printf("\n  sphere r 5: e1 %.6f e2 %.6f a %.6f %.6f %.6f, %d iterations, goodness %.2e\n", fit.model.e1, fit.model.e2,
              fit.model.a[0], fit.model.a[1], fit.model.a[2], fit.iterations, fit.goodness);
  DOUBLES_EQUAL(1.0, fit.model.e1, 1e-4);
  DOUBLES_EQUAL(1.0, fit.model.e2, 1e-4);
  for (double a : fit.model.a) DOUBLES_EQUAL(5.0, a, 1e-4);
  DOUBLES_EQUAL(0.0, norm(fit.model.center - Point3{1, 2, 3}), 1e-5);
  CHECK(fit.rms_radial_mm < 1e-5);
  CHECK(fit.shape == SuperquadricShape::kEllipsoid);
  CHECK(fit.rotationally_symmetric);
}

TEST(Superquadric, RecoversARotatedEllipsoidsSizesAndAxes) {
  const Superquadric truth = rotated(6, 4, 2.5, 1, 1, {10, -5, 20});
  const SuperquadricFit fit = fit_superquadric(sample(truth));
  // Sizes up to the order of the axes (x and y may swap).
  std::vector<double> got(fit.model.a, fit.model.a + 3), want = {6, 4, 2.5};
  std::sort(got.begin(), got.end());
  std::sort(want.begin(), want.end());
  for (int k = 0; k < 3; ++k) DOUBLES_EQUAL(want[static_cast<size_t>(k)], got[static_cast<size_t>(k)], 1e-3);
  DOUBLES_EQUAL(0.0, norm(fit.model.center - truth.center), 1e-4);
  CHECK(fit.rms_radial_mm < 1e-3);
  CHECK(!fit.rotationally_symmetric);
}

TEST(Superquadric, TellsACylinderAndABoxAndFindsTheCylindersAxis) {
  // A pin: 20 long, radius 4, Koivunen and Bajcsy 1992, Fig. 8 a)'s squareness.
  const Superquadric pin = rotated(4, 4, 10, 0.1, 1.0, {0, 0, 50});
  SuperquadricFit fit = fit_superquadric(sample(pin, 60));
  std::printf("  pin: e1 %.3f e2 %.3f a %.3f %.3f %.3f (%s), rms radial %.4f mm\n", fit.model.e1, fit.model.e2, fit.model.a[0],
              fit.model.a[1], fit.model.a[2], fit.description.c_str(), fit.rms_radial_mm);
  CHECK(fit.shape == SuperquadricShape::kCylinder);
  CHECK(fit.rotationally_symmetric);
  const Point3 axis{fit.model.axes[2][0], fit.model.axes[2][1], fit.model.axes[2][2]};
  const Point3 true_axis{pin.axes[2][0], pin.axes[2][1], pin.axes[2][2]};
  DOUBLES_EQUAL(1.0, std::fabs(dot(axis, true_axis)), 1e-3);
  // A block: Fig. 8 d).
  fit = fit_superquadric(sample(rotated(8, 5, 3, 0.1, 0.1, {0, 0, 0}), 60));
  std::printf("  block: e1 %.3f e2 %.3f (%s)\n", fit.model.e1, fit.model.e2, fit.description.c_str());
  CHECK(fit.shape == SuperquadricShape::kParallelepiped);
}

TEST(Superquadric, StaysCloseUnderMeasurementNoise) {
  Superquadric sphere;
  sphere.a[0] = sphere.a[1] = sphere.a[2] = 10;
  std::vector<Point3> p = sample(sphere);
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0, 0.01);
  for (Point3& q : p) q = q + Point3{noise(rng), noise(rng), noise(rng)};
  const SuperquadricFit fit = fit_superquadric(p);
  DOUBLES_EQUAL(1.0, fit.model.e1, 0.02);
  DOUBLES_EQUAL(1.0, fit.model.e2, 0.02);
  DOUBLES_EQUAL(10.0, fit.model.a[0], 0.02);
  DOUBLES_EQUAL(0.01 * std::sqrt(1.0 / 3.0) * std::sqrt(3.0), fit.rms_radial_mm, 0.004);
}

TEST(Superquadric, RefusesPointsWithoutVolume) {
  std::vector<Point3> plane;
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) plane.push_back({static_cast<double>(i), static_cast<double>(j), 2.0});
  }
  std::string error;
  try {
    fit_superquadric(plane);
  } catch (const FitError& e) {
    error = e.what();
  }
  STRCMP_CONTAINS("in a plane or on a line", error.c_str());
  CHECK_THROWS(FitError, fit_superquadric(std::vector<Point3>(5, Point3{1, 2, 3})));
}

TEST(Superquadric, ARotationalPartsAxisAndProfileFromSliceCircles) {
  // A turned part: radius 3 + 0.1 s along a tilted axis, s in [-10, 10] (a taper), sides only,
  // sampled at random as a scan would.
  const Point3 axis = (1.0 / std::sqrt(1.0 + 0.04 + 0.01)) * Point3{0.2, 0.1, 1.0};
  Point3 u = cross(axis, Point3{1, 0, 0});
  u = (1.0 / norm(u)) * u;
  const Point3 w = cross(axis, u);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> along(-10, 10), angle(0, 2 * M_PI);
  std::vector<Point3> p;
  for (int i = 0; i < 20000; ++i) {
    const double s = along(rng), a = angle(rng);
    p.push_back(Point3{5, 6, 7} + s * axis + (3 + 0.1 * s) * (std::cos(a) * u + std::sin(a) * w));
  }
  const SuperquadricFit fit = fit_superquadric(p);
  const RevolutionFit rev = fit_revolution(p, fit.model, 10);
  std::printf("  taper: superquadric %s; slice circles rms %.4f mm, axis (%.5f, %.5f, %.5f)\n", fit.description.c_str(),
              rev.rms_mm, rev.axis_direction.x, rev.axis_direction.y, rev.axis_direction.z);
  CHECK(fit.rotationally_symmetric);
  DOUBLES_EQUAL(1.0, dot(rev.axis_direction, axis), 1e-6);
  // A 2 mm slice of a 0.1 taper holds radii 0.2 mm apart: about 0.058 mm RMS around one circle.
  CHECK(rev.rms_mm < 0.07);
  LONGS_EQUAL(10, rev.slices.size());
  // The profile: radius 3 + 0.1 s at each slice's mean position along the axis (from (5, 6, 7)).
  for (const RevolutionSlice& slice : rev.slices) {
    const double s = dot(slice.center - Point3{5, 6, 7}, axis);
    DOUBLES_EQUAL(3 + 0.1 * s, slice.radius_mm, 0.005);
    DOUBLES_EQUAL(0.0, norm(slice.center - (Point3{5, 6, 7} + s * axis)), 0.005);
  }
}

TEST(Superquadric, TheSurfaceOfRevolutionFollowsTheSlices) {
  // A cylinder of radius 4 along z, with slices at four heights: the swept surface is within the
  // circle approximation's 4e-6 of the radius everywhere.
  RevolutionFit rev;
  rev.axis_point = {1, 2, 0};
  rev.axis_direction = {0, 0, 1};
  for (int k = 0; k < 4; ++k) {
    RevolutionSlice slice;
    slice.center = {1, 2, 5.0 * k};
    slice.radius_mm = 4;
    rev.slices.push_back(slice);
  }
  const BSplineSurface s = revolution_surface(rev, 32);
  std::string why;
  CHECK_TEXT(is_valid(s, &why), why.c_str());
  double worst = 0;
  for (int i = 0; i <= 50; ++i) {
    for (int j = 0; j <= 200; ++j) {
      const Point3 p = s.evaluate(s.u_min() + (s.u_max() - s.u_min()) * i / 50, s.v_min() + (s.v_max() - s.v_min()) * j / 200);
      worst = std::fmax(worst, std::fabs(std::hypot(p.x - 1, p.y - 2) - 4));
      CHECK(p.z > -1e-9 && p.z < 15 + 1e-9);
    }
  }
  std::printf("  surface of revolution, 32 control points around: radius error %.2e mm of 4\n", worst);
  CHECK(worst < 4 * 4e-6);
}

// Any superquadric with e1, e2 in [0.1, 1.9], axis-aligned or rotated, sizes in any order: the fit
// starts from each of the three principal directions as the object's z axis and keeps the best.
// Success: sizes (matched to the truth's axes by direction) within 1 %, e1 and e2 within 0.05, and
// the samples' RMS distance to the fitted surface along their rays within 0.5 % of the largest size.
TEST(Superquadric, RecoversAnySuperquadricWhicheverAxisIsItsZ) {
  const double sizes[][3] = {{40, 25, 12}, {12, 25, 40}, {25, 40, 12}, {20, 20, 35}, {30, 10, 10}};
  const double squareness[][2] = {{0.7, 1.3}, {0.1, 1.0}, {1.9, 0.5}, {1.0, 1.9}, {0.4, 0.1}, {1.5, 1.5}};
  int failures = 0, cases = 0;
  for (const auto& a : sizes) {
    for (const auto& e : squareness) {
      for (bool turn : {false, true}) {
        Superquadric truth = rotated(a[0], a[1], a[2], e[0], e[1], {5, -3, 20});
        if (!turn) {
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) truth.axes[r][c] = r == c ? 1 : 0;
        }
        const SuperquadricFit fit = fit_superquadric(sample(truth, 16));
        ++cases;
        const Superquadric& m = fit.model;
        // The fitted axis k matches the truth's axis it is most parallel to.
        bool sizes_ok = true;
        for (int k = 0; k < 3; ++k) {
          int match = 0;
          double best = -1;
          for (int t = 0; t < 3; ++t) {
            const double c = std::fabs(m.axes[k][0] * truth.axes[t][0] + m.axes[k][1] * truth.axes[t][1] +
                                       m.axes[k][2] * truth.axes[t][2]);
            if (c > best) best = c, match = t;
          }
          sizes_ok = sizes_ok && std::fabs(m.a[k] - truth.a[match]) <= 0.01 * truth.a[match];
        }
        // e1 and e2 belong to the z axis; where the fit's z is another of the truth's axes the shape
        // must be one that reads the same about it (a box is a box about any axis): judged by the
        // surface then.
        const double z_match = std::fabs(m.axes[2][0] * truth.axes[2][0] + m.axes[2][1] * truth.axes[2][1] +
                                         m.axes[2][2] * truth.axes[2][2]);
        const bool exponents_ok = z_match < 0.9 || (std::fabs(m.e1 - e[0]) <= 0.05 && std::fabs(m.e2 - e[1]) <= 0.05);
        const bool surface_ok = fit.rms_radial_mm <= 0.005 * std::max({a[0], a[1], a[2]});
        if (!surface_ok || !sizes_ok || !exponents_ok) {
          ++failures;
          std::printf("\n  a (%g %g %g) e (%g %g) %s: fitted a (%.2f %.2f %.2f) e (%.2f %.2f), RMS %.3f mm", a[0], a[1],
                      a[2], e[0], e[1], turn ? "rotated" : "aligned", m.a[0], m.a[1], m.a[2], m.e1, m.e2,
                      fit.rms_radial_mm);
        }
      }
    }
  }
  std::printf("\n  superquadrics recovered: %d of %d", cases - failures, cases);
  LONGS_EQUAL(0, failures);
}

// The parameters' standard uncertainties against the spread of fits of noisy replicas (Monte
// Carlo): 80 replicas of a 40 x 25 x 12 mm superquadric (e1 0.7, e2 1.3) sampled at 480 points
// with 20 um of noise on every coordinate. 80 replicas estimate a spread to about 8 %; the
// predicted u must agree within 25 % (measured: 16 % at worst, the largest size).
TEST(Superquadric, ParameterUncertaintiesAgreeWithTheSpreadOfNoisyRefits) {
  Superquadric truth = rotated(40, 25, 12, 0.7, 1.3, {5, -3, 20});
  const std::vector<Point3> clean = sample(truth, 16);
  std::mt19937 rng(21);
  std::normal_distribution<double> noise(0.0, 0.02);
  constexpr int kReplicas = 80;
  double sum[5] = {}, sum_sq[5] = {}, predicted[5] = {};
  for (int k = 0; k < kReplicas; ++k) {
    std::vector<Point3> p = clean;
    for (Point3& q : p) q += Point3{noise(rng), noise(rng), noise(rng)};
    const SuperquadricFit f = fit_superquadric(p);
    CHECK(f.uncertainty.computed);
    // Sizes in the fit's own axis order: match them to the truth's by length.
    double a[3] = {f.model.a[0], f.model.a[1], f.model.a[2]}, ua[3] = {f.uncertainty.a_mm[0], f.uncertainty.a_mm[1], f.uncertainty.a_mm[2]};
    const double values[5] = {*std::max_element(a, a + 3), *std::min_element(a, a + 3), f.model.e1, f.model.e2, f.model.center.x};
    const double u[5] = {ua[std::max_element(a, a + 3) - a], ua[std::min_element(a, a + 3) - a], f.uncertainty.e1, f.uncertainty.e2,
                         f.uncertainty.center_mm[0]};
    for (int m = 0; m < 5; ++m) {
      sum[m] += values[m];
      sum_sq[m] += values[m] * values[m];
      predicted[m] += u[m] / kReplicas;
    }
  }
  const char* names[5] = {"largest size", "smallest size", "e1", "e2", "centre x"};
  for (int m = 0; m < 5; ++m) {
    const double mean = sum[m] / kReplicas;
    const double spread = std::sqrt((sum_sq[m] - kReplicas * mean * mean) / (kReplicas - 1));
    std::printf("\n  %s: predicted u %.5f, spread of %d refits %.5f", names[m], predicted[m], kReplicas, spread);
    CHECK(std::fabs(predicted[m] / spread - 1) <= 0.25);
  }
}

// The second-derivative bound from the control net: never below the surface's own second
// derivatives (finite differences of its evaluation), exact on a quadratic, none across a crease.
#include "host/geometry/curvature_bound.h"

#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace dg::host;

namespace {

// A bicubic with a random net over [0, 1]^2 and `interior` knots per direction, one of them doubled
// (C1 there) and, with `crease`, one tripled at 0.5 (C0 there).
BSplineSurface random_surface(uint32_t seed, bool crease) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0), height(-2.0, 2.0);
  auto knots = [&](std::vector<double> interior) {
    std::vector<double> k(4, 0.0);
    std::sort(interior.begin(), interior.end());
    k.insert(k.end(), interior.begin(), interior.end());
    k.insert(k.end(), 4, 1.0);
    return k;
  };
  std::vector<double> inner_u{0.13, 0.3, 0.3, 0.71, 0.85}, inner_v{0.2, 0.41, 0.66, 0.66};
  if (crease) inner_u = {0.13, 0.5, 0.5, 0.5, 0.85};
  BSplineSurface s;
  s.knots_u = knots(inner_u);
  s.knots_v = knots(inner_v);
  s.count_u = static_cast<int>(s.knots_u.size()) - 4;
  s.count_v = static_cast<int>(s.knots_v.size()) - 4;
  for (int i = 0; i < s.count_u; ++i) {
    for (int j = 0; j < s.count_v; ++j) {
      s.control.push_back({greville(s.knots_u, 3, i) * 40 + 0.3 * height(rng), greville(s.knots_v, 3, j) * 30, height(rng)});
    }
  }
  return s;
}

// |d^2 S / dt^2| along the unit direction (cu, cv) at (u, v), largest coordinate, by central differences.
double second_along(const BSplineSurface& s, double u, double v, double cu, double cv, double h) {
  const Point3 a = s.evaluate(u - h * cu, v - h * cv), b = s.evaluate(u, v), c = s.evaluate(u + h * cu, v + h * cv);
  return std::max({std::fabs(a.x - 2 * b.x + c.x), std::fabs(a.y - 2 * b.y + c.y), std::fabs(a.z - 2 * b.z + c.z)}) / (h * h);
}

}  // namespace

TEST_GROUP(CurvatureBound){};

TEST(CurvatureBound, IsNeverBelowTheSurfacesOwnSecondDerivativeInAnyDirection) {
  for (uint32_t seed = 1; seed <= 5; ++seed) {
    const BSplineSurface s = random_surface(seed, false);
    const CurvatureBound bound(s);
    std::mt19937 rng(seed + 100);
    std::uniform_real_distribution<double> unit(0.0, 1.0), angle(0.0, 6.283185307179586), size(0.0, 0.3);
    for (int n = 0; n < 3000; ++n) {
      const double u0 = unit(rng) * 0.7, v0 = unit(rng) * 0.7, du = size(rng), dv = size(rng);
      const double m = bound.along_any_direction(u0, u0 + du, v0, v0 + dv);
      CHECK(std::isfinite(m));
      // A place inside the box, away from its edges by the difference step.
      const double h = 1e-4, u = u0 + h + (du - 2 * h) * unit(rng), v = v0 + h + (dv - 2 * h) * unit(rng);
      if (du < 3 * h || dv < 3 * h) continue;
      const double a = angle(rng);
      CHECK(second_along(s, u, v, std::cos(a), std::sin(a), h) <= m * (1 + 1e-4) + 1e-6);
    }
  }
}

TEST(CurvatureBound, IsExactOnAQuadratic) {
  // z = 3 u^2: the net of a quadratic is its blossom (u_a u_b + u_b u_c + u_c u_a) / 3 at each
  // control point's three interior knots, whose second differences are all 6; x and y are linear.
  BSplineSurface s;
  s.knots_u = {0, 0, 0, 0, 0.2, 0.45, 0.7, 1, 1, 1, 1};
  s.knots_v = {0, 0, 0, 0, 0.5, 1, 1, 1, 1};
  s.count_u = 7;
  s.count_v = 5;
  for (int i = 0; i < s.count_u; ++i) {
    const double a = s.knots_u[static_cast<size_t>(i + 1)], b = s.knots_u[static_cast<size_t>(i + 2)], c = s.knots_u[static_cast<size_t>(i + 3)];
    for (int j = 0; j < s.count_v; ++j) s.control.push_back({40 * greville(s.knots_u, 3, i), 30 * greville(s.knots_v, 3, j), 3 * (a * b + b * c + c * a) / 3});
  }
  const Point3 mid = s.evaluate(0.6, 0.3);
  DOUBLES_EQUAL(3 * 0.36, mid.z, 1e-12);
  const CurvatureBound bound(s);
  DOUBLES_EQUAL(6.0, bound.along_any_direction(0.1, 0.9, 0.0, 1.0), 1e-9);
  DOUBLES_EQUAL(6.0, bound.along_any_direction(0.5, 0.5, 0.5, 0.5), 1e-9);
}

TEST(CurvatureBound, HasNoBoundAcrossACreaseOnlyBesideIt) {
  const BSplineSurface s = random_surface(7, true);
  const CurvatureBound bound(s);
  CHECK(std::isinf(bound.along_any_direction(0.45, 0.55, 0.2, 0.3)));
  CHECK(std::isinf(bound.along_any_direction(0.55, 0.45, 0.2, 0.3)));  // either order of the ends
  CHECK(std::isfinite(bound.along_any_direction(0.3, 0.49, 0.2, 0.3)));
  CHECK(std::isfinite(bound.along_any_direction(0.5, 0.7, 0.2, 0.3)));  // from the crease on, one piece
  // A double knot (C1) is no crease.
  CHECK(std::isfinite(bound.along_any_direction(0.2, 0.4, 0.5, 0.8)));
}

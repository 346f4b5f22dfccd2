// The power-form patches against the B-spline form they come from: points and derivatives at
// random places, on knots (single, doubled and tripled), beyond the domain, and for other degrees;
// closest points on either form agree.
#include "host/geometry/patch_form.h"

#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "host/geometry/closest_point.h"
#include "host/geometry/vec3.h"

using namespace dg::host;

namespace {

// A surface of degrees (p, q) with a random net over a 40 x 30 mm rectangle, interior knots with
// a double and (for p >= 3) a triple one, so spans of zero width lie between patches.
BSplineSurface random_surface(uint32_t seed, int p, int q) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> height(-2.0, 2.0);
  auto knots = [&](int degree, std::vector<double> interior) {
    std::vector<double> k(static_cast<size_t>(degree + 1), 0.0);
    k.insert(k.end(), interior.begin(), interior.end());
    k.insert(k.end(), static_cast<size_t>(degree + 1), 1.0);
    return k;
  };
  BSplineSurface s;
  s.degree_u = p;
  s.degree_v = q;
  s.knots_u = knots(p, p >= 3 ? std::vector<double>{0.13, 0.3, 0.3, 0.5, 0.5, 0.5, 0.85} : std::vector<double>{0.13, 0.3, 0.3, 0.85});
  s.knots_v = knots(q, {0.2, 0.41, 0.66, 0.66, 0.9});
  s.count_u = static_cast<int>(s.knots_u.size()) - p - 1;
  s.count_v = static_cast<int>(s.knots_v.size()) - q - 1;
  for (int i = 0; i < s.count_u; ++i) {
    for (int j = 0; j < s.count_v; ++j) {
      s.control.push_back({greville(s.knots_u, p, i) * 40 + 0.3 * height(rng), greville(s.knots_v, q, j) * 30, height(rng)});
    }
  }
  return s;
}

// Both forms at (u, v): the largest difference of the points and of the derivatives, in mm.
void check_agrees(const BSplineSurface& s, const PatchForm& form, double u, double v) {
  Point3 a, au, av, b, bu, bv;
  s.evaluate(u, v, a, au, av);
  form.evaluate(u, v, b, bu, bv);
  const Point3 only = form.evaluate(u, v);
  DOUBLES_EQUAL(0.0, norm(a - b), 1e-11);
  DOUBLES_EQUAL(0.0, norm(a - only), 1e-11);
  // The derivatives are mm per unit of parameter: up to a few hundred here.
  DOUBLES_EQUAL(0.0, norm(au - bu), 1e-9);
  DOUBLES_EQUAL(0.0, norm(av - bv), 1e-9);
}

}  // namespace

TEST_GROUP(PatchForm) {};

TEST(PatchForm, AgreesWithTheBSplineFormAtRandomPlaces) {
  for (uint32_t seed = 1; seed <= 4; ++seed) {
    const BSplineSurface s = random_surface(seed, 3, 3);
    const PatchForm form(s);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int k = 0; k < 2000; ++k) check_agrees(s, form, unit(rng), unit(rng));
  }
}

TEST(PatchForm, AgreesOnEveryKnotAndAtTheDomainsEnds) {
  const BSplineSurface s = random_surface(7, 3, 3);
  const PatchForm form(s);
  DOUBLES_EQUAL(0.0, form.u_min(), 0);
  DOUBLES_EQUAL(1.0, form.u_max(), 0);
  for (double u : s.knots_u) {
    for (double v : s.knots_v) check_agrees(s, form, u, v);
  }
  // Just below and above a tripled knot, where the surface is only C0.
  for (double u : {std::nextafter(0.5, 0.0), 0.5, std::nextafter(0.5, 1.0)}) check_agrees(s, form, u, 0.37);
}

TEST(PatchForm, ExtendsTheEndPatchesBeyondTheDomainAsTheBSplineFormDoes) {
  const BSplineSurface s = random_surface(3, 3, 3);
  const PatchForm form(s);
  for (double u : {-0.05, -0.01, 1.01, 1.05}) {
    for (double v : {-0.03, 0.5, 1.02}) check_agrees(s, form, u, v);
  }
}

TEST(PatchForm, AgreesForOtherDegrees) {
  for (const auto& [p, q] : {std::pair{1, 1}, std::pair{2, 4}, std::pair{5, 2}, std::pair{3, 1}}) {
    const BSplineSurface s = random_surface(11, p, q);
    const PatchForm form(s);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int k = 0; k < 500; ++k) check_agrees(s, form, unit(rng), unit(rng));
  }
}

TEST(PatchForm, ClosestPointsOnEitherFormAgree) {
  const BSplineSurface s = random_surface(2, 3, 3);
  const PatchForm form(s);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0), off(-0.5, 0.5);
  for (int k = 0; k < 500; ++k) {
    const double u = unit(rng), v = unit(rng);
    const Point3 p = s.evaluate(u, v) + Point3{off(rng), off(rng), off(rng)};
    const Closest a = closest_point(s, p, u, v), b = closest_point(form, p, u, v);
    DOUBLES_EQUAL(a.distance, b.distance, 1e-9);
    DOUBLES_EQUAL(a.u, b.u, 1e-7);
    DOUBLES_EQUAL(a.v, b.v, 1e-7);
  }
}

TEST(PatchForm, PaysOnlyForManyEvaluations) {
  const BSplineSurface s = random_surface(1, 3, 3);
  CHECK_FALSE(patch_form_pays(s, 100));
  CHECK_TRUE(patch_form_pays(s, 1000000));
}

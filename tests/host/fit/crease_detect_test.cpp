// Crease and step detection: creases across the part are found and make the fit exact there;
// creases that wander across the part and smooth curvature are left alone.
#include "host/fit/crease_detect.h"

#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "host/fit/bspline_fit.h"
#include "host/geometry/distance_stats.h"
#include "host/geometry/closest_point.h"
#include "host/fit/orthogonal_distances.h"

using namespace dg::host;

namespace {

constexpr double kNoise = 0.002;

PointCloud grid(double (*z)(double, double), double noise_mm) {
  std::mt19937 rng(17);
  std::normal_distribution<double> gauge(0.0, noise_mm);
  PointCloud c;
  c.line = std::vector<uint32_t>();
  for (int j = 0; j <= 30; ++j) {
    for (int k = 0; k <= 40; ++k) {
      const int i = (j % 2) ? 40 - k : k;  // serpentine
      c.points.push_back({1.0 * i, 1.0 * j, z(i, j) + (noise_mm > 0 ? gauge(rng) : 0.0)});
      c.line->push_back(static_cast<uint32_t>(j));
    }
  }
  return c;
}

double groove(double x, double) { return 5.0 - 0.3 * std::fabs(x - 20.0); }
double ridge_along_x(double, double y) { return 2.0 + 0.2 * std::fabs(y - 15.0); }
double step(double x, double y) { return (x < 25.5 ? 1.0 : 3.0) + 0.01 * y; }
double dome(double x, double y) {
  const double r2 = (x - 20) * (x - 20) + (y - 15) * (y - 15);
  return r2 < 144 ? 2.0 + std::sqrt(900 - r2) - std::sqrt(900 - 144.0) : 2.0;
}
double wave(double x, double y) { return 2.0 + std::sin(x / 6.0) * std::cos(y / 8.0); }

Creases creases_of(double (*z)(double, double)) {
  const PointCloud c = grid(z, kNoise);
  return detect_creases(c, parameterize(c, Parameterization::kTableXy), kNoise);
}

double max_distance(const PointCloud& c, int ctrl, const Creases& creases) {
  const Parameters p = parameterize(c, Parameterization::kTableXy);
  LsqSpec spec;
  spec.knots_u = with_crease_knots(clamped_uniform_knots(ctrl, 3), creases.u, 3);
  spec.knots_v = with_crease_knots(clamped_uniform_knots(ctrl, 3), creases.v, 3);
  return distance_stats(orthogonal_distances(fit_least_squares(c.points, p, nullptr, spec), c.points, p)).max_abs;
}

}  // namespace

TEST_GROUP(CreaseDetect){};

TEST(CreaseDetect, FindsAGrooveAcrossEveryLine) {
  const Creases c = creases_of(groove);
  LONGS_EQUAL(1, c.u.size());
  DOUBLES_EQUAL(0.5, c.u[0], 1e-9);
  LONGS_EQUAL(0, c.v.size());
}

TEST(CreaseDetect, FindsARidgeAlongXInTheOtherDirection) {
  const Creases c = creases_of(ridge_along_x);
  LONGS_EQUAL(0, c.u.size());
  LONGS_EQUAL(1, c.v.size());
  DOUBLES_EQUAL(0.5, c.v[0], 1e-9);
}

TEST(CreaseDetect, BracketsAStepWithAKnotAtEachEndOfItsRamp) {
  const Creases c = creases_of(step);
  LONGS_EQUAL(2, c.u.size());
  DOUBLES_EQUAL(25.0 / 40, c.u[0], 1e-9);
  DOUBLES_EQUAL(26.0 / 40, c.u[1], 1e-9);
}

TEST(CreaseDetect, LeavesSmoothPartsAndWanderingCreasesAlone) {
  const Creases w = creases_of(wave);
  LONGS_EQUAL(0, w.u.size() + w.v.size());
  const Creases d = creases_of(dome);
  LONGS_EQUAL(0, d.u.size() + d.v.size());
}

TEST(CreaseDetect, MultipleKnotsMakeTheFitFollowTheCreaseAndTheStep) {
  for (auto z : {groove, step}) {
    const PointCloud c = grid(z, kNoise);
    const Creases found = detect_creases(c, parameterize(c, Parameterization::kTableXy), kNoise);
    // Piecewise linear across the crease: with C0 knots a 4 x 4 net holds it to the noise; without
    // them even 12 x 12 control points round the crease off by tens of micrometres or more.
    CHECK(max_distance(c, 4, found) < 5 * kNoise);
    CHECK(max_distance(c, 12, Creases{}) > 10 * kNoise);
  }
}

TEST(CreaseDetect, KeepsACreaseKnotAtMultiplicityDegreeWhereAKnotAlreadyIs) {
  const std::vector<double> knots = with_crease_knots(clamped_uniform_knots(5, 3), {0.5, 0.0, 1.0}, 3);
  LONGS_EQUAL(3, std::count(knots.begin(), knots.end(), 0.5));
  LONGS_EQUAL(4, std::count(knots.begin(), knots.end(), 0.0));
}

TEST(CreaseDetect, NeedsScanLines) {
  PointCloud c = grid(groove, kNoise);
  c.line.reset();
  const Creases found = detect_creases(c, parameterize(c, Parameterization::kTableXy), kNoise);
  LONGS_EQUAL(0, found.u.size() + found.v.size());
}

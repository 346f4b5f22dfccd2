// Local polynomial fits, upright and in a tilted frame, against surfaces known exactly.
#include "host/scan/local_polynomial.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <vector>

using dg::host::fit_local_polynomial;
using dg::host::fit_tilted_polynomial;
using dg::host::LocalPolynomial;
using dg::host::Point3;

namespace {

// A ball of radius 12.7 mm about the origin (the reference sphere's size): its height at (x, y).
double ball_z(double x, double y) { return std::sqrt(12.7 * 12.7 - x * x - y * y); }

// The 5 x 5 grid at 1 mm about (cx, cy) on the ball, without its centre.
std::vector<Point3> ball_window(double cx, double cy) {
  std::vector<Point3> points;
  for (int dy = -2; dy <= 2; ++dy) {
    for (int dx = -2; dx <= 2; ++dx) {
      if (dx != 0 || dy != 0) points.push_back({cx + dx, cy + dy, ball_z(cx + dx, cy + dy)});
    }
  }
  return points;
}

std::vector<size_t> all_of(const std::vector<Point3>& points) {
  std::vector<size_t> indices(points.size());
  for (size_t k = 0; k < indices.size(); ++k) indices[k] = k;
  return indices;
}

}  // namespace

TEST_GROUP(LocalPolynomial){};

TEST(LocalPolynomial, ATiltedModelsHeightIsExactOnAPlaneWhateverItsFrame) {
  // z = 1 + 2x - 0.5y, fitted as a plane in a frame tilted to a normal that is not the plane's:
  // the height above any (x, y) comes back exact, as the upright fit's does.
  std::vector<Point3> points;
  for (int y = -2; y <= 2; ++y) {
    for (int x = -2; x <= 2; ++x) points.push_back({10.0 + x, 5.0 + y, 1 + 2 * (10.0 + x) - 0.5 * (5.0 + y)});
  }
  const Point3 centre{10, 5, 19};
  LocalPolynomial tilted, upright;
  CHECK(fit_tilted_polynomial(points, all_of(points), centre, {-1.5, 0.3, 1}, 1, tilted));
  CHECK(fit_local_polynomial(points, all_of(points), centre, 1, upright));
  CHECK(tilted.tilted);
  for (const auto& [x, y] : {std::pair{10.0, 5.0}, std::pair{8.3, 6.9}, std::pair{12.5, 3.1}}) {
    DOUBLES_EQUAL(1 + 2 * x - 0.5 * y, tilted.at(x, y), 1e-9);
    DOUBLES_EQUAL(1 + 2 * x - 0.5 * y, upright.at(x, y), 1e-9);
  }
}

TEST(LocalPolynomial, ATiltedQuadraticFollowsASpheresFlankThatAnUprightOneMisses) {
  // 9 to 10 mm from the ball's axis its slope is 1.1 to 1.3: an upright quadratic over 5 x 5 mm
  // misses the centre's true height by 38 to 56 um, one in the frame of the upright plane's normal
  // by 5 to 6 um, and as little half a step away.
  for (const auto& [cx, cy] : {std::pair{10.0, 0.0}, std::pair{6.0, 7.0}, std::pair{-9.0, 3.0}}) {
    const std::vector<Point3> points = ball_window(cx, cy);
    const Point3 centre{cx, cy, ball_z(cx, cy)};
    LocalPolynomial upright, plane, tilted;
    CHECK(fit_local_polynomial(points, all_of(points), centre, 2, upright));
    CHECK(fit_local_polynomial(points, all_of(points), centre, 1, plane));
    const double normal[3] = {-plane.c[1] / plane.scale_x, -plane.c[2] / plane.scale_y, 1};
    CHECK(fit_tilted_polynomial(points, all_of(points), centre, normal, 2, tilted));
    const double truth = ball_z(cx, cy);
    CHECK(std::fabs(upright.at(cx, cy) - truth) > 0.03);
    CHECK(std::fabs(tilted.at(cx, cy) - truth) < 0.008);
    // And between the samples too, half a step from the centre.
    CHECK(std::fabs(tilted.at(cx + 0.5, cy - 0.5) - ball_z(cx + 0.5, cy - 0.5)) < 0.008);
  }
}

TEST(LocalPolynomial, ATiltedFitRefusesANormalThatIsNotUpward) {
  const std::vector<Point3> points = ball_window(5, 0);
  LocalPolynomial model;
  CHECK_FALSE(fit_tilted_polynomial(points, all_of(points), points[0], {0.5, 0, -1}, 2, model));
  CHECK_FALSE(fit_tilted_polynomial(points, all_of(points), points[0], {1, 0, 0}, 2, model));
}

TEST(LocalPolynomial, ATiltedModelHasNoHeightWhereTheVerticalMissesItsSurface) {
  // The parabola w = u^2 in a frame tilted 80 degrees (normal (sin, 0, cos)): the vertical through
  // (x, 0) meets it where sin x + cos z = (cos x - sin z)^2, a quadratic in z whose discriminant is
  // cos^2 + 4 sin x. Below x = -cos^2 / (4 sin) = -0.0077 mm it has no root: there is no height, and
  // height() says so. Above it there are two, and the one height() gives lies on the surface.
  const double theta = 80.0 * M_PI / 180.0, s = std::sin(theta), c = std::cos(theta);
  LocalPolynomial model;
  model.order = 2;
  model.tilted = true;
  model.centre = {0, 0, 0};
  const double u[3] = {c, 0, -s}, n[3] = {s, 0, c};
  for (int k = 0; k < 3; ++k) model.axis_u[k] = u[k], model.normal[k] = n[k];
  model.c[3] = 1.0;
  double z = 0;
  for (double x : {-0.5, -0.05, -0.01}) CHECK_FALSE(model.height(x, 0, z));
  for (double x : {0.0, 0.01, 0.3}) {
    CHECK(model.height(x, 0, z));
    const double along_u = c * x - s * z, along_n = s * x + c * z;
    DOUBLES_EQUAL(along_u * along_u, along_n, 1e-9);
  }
  // An upright model always has a height.
  LocalPolynomial upright;
  upright.order = 2;
  upright.c[3] = 1.0;
  CHECK(upright.height(-0.5, 0, z));
  DOUBLES_EQUAL(0.25, z, 1e-12);
  // The judges read heights through height_or_huge: no number where there is no height, so that
  // no bound is ever met there; the height itself where there is one; at() for an upright model.
  for (double x : {-0.5, -0.05, -0.01}) CHECK(model.height_or_huge(x, 0) == HUGE_VAL);
  for (double x : {0.0, 0.01, 0.3}) {
    CHECK(model.height(x, 0, z));
    CHECK(model.height_or_huge(x, 0) == z);
  }
  CHECK(upright.height_or_huge(-0.5, 0) == upright.at(-0.5, 0));
}

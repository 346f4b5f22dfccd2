// Clamping by knot insertion: the same surface, now with its edges on the first and last rows.
#include "host/geometry/clamp.h"

#include <CppUTest/TestHarness.h>

#include "host/geometry/vec3.h"
#include "tests/support/sample_surfaces.h"

using namespace dg::host;

TEST_GROUP(Clamp){};

TEST(Clamp, KeepsTheSurfaceAndPutsItsCornersOnControlPoints) {
  const BSplineSurface net = dg::test::unclamped_sample();
  const BSplineSurface c = clamp_ends(net);
  LONGS_EQUAL(5, c.count_u);  // one interior knot (0.5) and degree 3: 5 control points
  LONGS_EQUAL(5, c.count_v);
  DOUBLES_EQUAL(0.0, c.knots_u.front(), 0);
  DOUBLES_EQUAL(1.0, c.knots_u.back(), 0);
  for (int a = 0; a <= 16; ++a) {
    for (int b = 0; b <= 16; ++b) {
      const double u = a / 16.0, v = b / 16.0;
      DOUBLES_EQUAL(0.0, norm(net.evaluate(u, v) - c.evaluate(u, v)), 1e-12);
    }
  }
  DOUBLES_EQUAL(0.0, norm(net.evaluate(0, 0) - c.at(0, 0)), 1e-12);
  DOUBLES_EQUAL(0.0, norm(net.evaluate(1, 1) - c.at(4, 4)), 1e-12);
}

TEST(Clamp, LeavesAClampedSurfaceAlone) {
  const BSplineSurface s = dg::test::clamped_sample();
  const BSplineSurface c = clamp_ends(s);
  CHECK(s.knots_u == c.knots_u);
  CHECK(s.knots_v == c.knots_v);
  LONGS_EQUAL(s.control.size(), c.control.size());
}

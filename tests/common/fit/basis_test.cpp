// Bernstein and B-spline bases: partition of unity, Hamdan 2010, eq. 6, known values, derivatives.
#include "common/fit/bernstein.h"
#include "common/fit/bspline_basis.h"
#include "common/fit/height_field_fit.h"

#include <CppUTest/TestHarness.h>

#include <cmath>

using namespace dg::fit;

TEST_GROUP(Basis){};

TEST(Basis, CubicBernsteinIsSeed000Equation6) {
  for (double u = 0; u <= 1.0; u += 0.125) {
    double b[4];
    bernstein(3, u, b);
    DOUBLES_EQUAL(1 - 3 * u + 3 * u * u - u * u * u, b[0], 1e-15);
    DOUBLES_EQUAL(3 * u - 6 * u * u + 3 * u * u * u, b[1], 1e-15);
    DOUBLES_EQUAL(3 * u * u - 3 * u * u * u, b[2], 1e-15);
    DOUBLES_EQUAL(u * u * u, b[3], 1e-15);
  }
}

TEST(Basis, BernsteinDerivativeMatchesDifferences) {
  const double u = 0.37, h = 1e-6;
  for (int degree = 1; degree <= 5; ++degree) {
    double d[8], lo[8], hi[8];
    bernstein_derivative(degree, u, d);
    bernstein(degree, u - h, lo);
    bernstein(degree, u + h, hi);
    for (int i = 0; i <= degree; ++i) DOUBLES_EQUAL((hi[i] - lo[i]) / (2 * h), d[i], 1e-7);
  }
}

TEST(Basis, FixedPointBernsteinIsWithinOneUnitOfDouble) {
  for (int k = 0; k <= 64; ++k) {
    dg::fx::Q<30> q[4];
    double d[4];
    bernstein(3, dg::fx::Q<30>::from_ratio(k, 64), q);
    bernstein(3, k / 64.0, d);
    for (int i = 0; i < 4; ++i) DOUBLES_EQUAL(d[i], q[i].raw / 1073741824.0, 8.0 / 1073741824.0);
  }
}

TEST(Basis, BSplineIsAPartitionOfUnityOnANonUniformClampedKnotVector) {
  const double knots[] = {0, 0, 0, 0, 0.1, 0.5, 0.5, 0.8, 1, 1, 1, 1};  // 8 control points, cubic
  for (double u = 0; u <= 1.0; u += 0.01) {
    const int span = find_span(8, 3, u, knots);
    CHECK(knots[span] <= u && (u < knots[span + 1] || span == 7));
    double n[4];
    bspline_basis(span, 3, u, knots, n);
    DOUBLES_EQUAL(1.0, n[0] + n[1] + n[2] + n[3], 1e-14);
    for (double v : n) CHECK(v >= -1e-15);
  }
}

TEST(Basis, BSplineOnBezierKnotsIsBernstein) {
  const double knots[] = {0, 0, 0, 0, 1, 1, 1, 1};
  for (double u = 0; u <= 1.0; u += 0.1) {
    double n[4], b[4], dn[4], db[4];
    bspline_basis(find_span(4, 3, u, knots), 3, u, knots, n, dn);
    bernstein(3, u, b);
    bernstein_derivative(3, u, db);
    for (int i = 0; i < 4; ++i) {
      DOUBLES_EQUAL(b[i], n[i], 1e-15);
      DOUBLES_EQUAL(db[i], dn[i], 1e-13);
    }
  }
}

TEST(Basis, BSplineDerivativeMatchesDifferences) {
  const double knots[] = {0, 0, 0, 0.2, 0.45, 0.7, 1, 1, 1};  // quadratic, 6 control points
  const double h = 1e-7;
  for (double u = 0.05; u < 1.0; u += 0.1) {
    const int span = find_span(6, 2, u, knots);
    double n[3], d[3], lo[3], hi[3];
    bspline_basis(span, 2, u, knots, n, d);
    bspline_basis(span, 2, u - h, knots, lo);
    bspline_basis(span, 2, u + h, knots, hi);
    for (int i = 0; i < 3; ++i) DOUBLES_EQUAL((hi[i] - lo[i]) / (2 * h), d[i], 1e-6);
  }
}

TEST(Basis, UniformCubicSpanBasisMatchesTheGeneralRecurrence) {
  // Knots (i - 3) / 3 for i = 0..9: 6 control points, 3 spans on [0, 1].
  double knots[10];
  for (int i = 0; i < 10; ++i) knots[i] = (i - 3) / 3.0;
  for (double u = 0; u <= 1.0; u += 0.05) {
    double general[4], uniform[4];
    const int span = find_span(6, 3, u, knots);
    bspline_basis(span, 3, u, knots, general);
    int first = 0;
    UniformCubicBasis<6>::basis<FloatingPolicy<double>>(u, uniform, first);
    LONGS_EQUAL(span - 3, first);
    for (int i = 0; i < 4; ++i) DOUBLES_EQUAL(general[i], uniform[i], 1e-14);
  }
}

// The streaming height-field fits: exact reproduction, fixed point against double, degenerate data.
#include "common/fit/height_field_fit.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <cstdlib>
#include <new>
#include <random>

using namespace dg::fit;

namespace {

using DoubleBezier = HeightFieldFit<FloatingPolicy<double>, BezierBasis>;
using FixedBezier = HeightFieldFit<FixedPolicy<15>, BezierBasis>;
using DoubleNet = HeightFieldFit<FloatingPolicy<double>, UniformCubicBasis<5>>;
using FixedNet = HeightFieldFit<FixedPolicy<15>, UniformCubicBasis<5>>;

// Evaluates a fitted Bezier patch (control heights in mm) at a table position, mm.
double bezier_at(const double (&p)[4][4], const FitRegion& r, double x_mm, double y_mm) {
  const double u = (x_mm * 1e6 - r.x_min_nm) / (r.x_max_nm - r.x_min_nm);
  const double v = (y_mm * 1e6 - r.y_min_nm) / (r.y_max_nm - r.y_min_nm);
  double bu[4], bv[4];
  bernstein(3, u, bu);
  bernstein(3, v, bv);
  double z = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) z += p[i][j] * bu[i] * bv[j];
  return z;
}

double net_at(const double (&p)[5][5], const FitRegion& r, double x_mm, double y_mm) {
  const double u = (x_mm * 1e6 - r.x_min_nm) / (r.x_max_nm - r.x_min_nm);
  const double v = (y_mm * 1e6 - r.y_min_nm) / (r.y_max_nm - r.y_min_nm);
  double bu[4], bv[4];
  int su = 0, sv = 0;
  UniformCubicBasis<5>::basis<FloatingPolicy<double>>(u, bu, su);
  UniformCubicBasis<5>::basis<FloatingPolicy<double>>(v, bv, sv);
  double z = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) z += p[su + i][sv + j] * bu[i] * bv[j];
  return z;
}

// A dome of radius 400 mm over a 200 mm table, heights rounded to the gauge's 1 um.
int32_t dome_z_nm(int32_t x_nm, int32_t y_nm) {
  const double x = x_nm * 1e-6 - 100, y = y_nm * 1e-6 - 100;
  const double z_mm = std::sqrt(400.0 * 400.0 - x * x - y * y) - 350.0;
  return static_cast<int32_t>(std::lround(z_mm * 1000.0)) * 1000;
}

const FitRegion kTable{0, 200000000, 0, 200000000};

// The largest gap between the fixed-point and the double fits over the region, mm, of heights
// z_mm(x, y) read to 1 um on a grid of `step_mm`.
struct Gap {
  double bezier_mm = 0, net_mm = 0;
  uint32_t points = 0;
};
template <typename Z>
Gap fixed_against_double(const FitRegion& region, double step_mm, Z z_mm) {
  DoubleBezier double_bezier;
  FixedBezier fixed_bezier;
  DoubleNet double_net;
  FixedNet fixed_net;
  double_bezier.begin(region);
  fixed_bezier.begin(region);
  double_net.begin(region);
  fixed_net.begin(region);
  const double x0 = region.x_min_nm * 1e-6, x1 = region.x_max_nm * 1e-6;
  const double y0 = region.y_min_nm * 1e-6, y1 = region.y_max_nm * 1e-6;
  for (double y = y0; y <= y1 + 1e-9; y += step_mm)
    for (double x = x0; x <= x1 + 1e-9; x += step_mm) {
      const int32_t x_nm = static_cast<int32_t>(std::lround(x * 1e6)), y_nm = static_cast<int32_t>(std::lround(y * 1e6));
      const int32_t z_nm = static_cast<int32_t>(std::lround(z_mm(x, y) * 1e3)) * 1000;
      double_bezier.add(x_nm, y_nm, z_nm);
      fixed_bezier.add(x_nm, y_nm, z_nm);
      double_net.add(x_nm, y_nm, z_nm);
      fixed_net.add(x_nm, y_nm, z_nm);
    }
  double pd[4][4], nd[5][5], pf_mm[4][4], nf_mm[5][5];
  int32_t pf[4][4], nf[5][5];
  static DoubleBezier::Workspace w1;
  static FixedBezier::Workspace w2;
  static DoubleNet::Workspace w3;
  static FixedNet::Workspace w4;
  CHECK(dg::Status::kOk == double_bezier.solve(pd, w1));
  CHECK(dg::Status::kOk == fixed_bezier.solve(pf, w2));
  CHECK(dg::Status::kOk == double_net.solve(nd, w3));
  CHECK(dg::Status::kOk == fixed_net.solve(nf, w4));
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) pf_mm[i][j] = pf[i][j] * 1e-6;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) nf_mm[i][j] = nf[i][j] * 1e-6;
  Gap gap;
  gap.points = fixed_bezier.count();
  for (double y = y0; y <= y1 + 1e-9; y += (y1 - y0) / 80)
    for (double x = x0; x <= x1 + 1e-9; x += (x1 - x0) / 80) {
      gap.bezier_mm = std::fmax(gap.bezier_mm, std::fabs(bezier_at(pd, region, x, y) - bezier_at(pf_mm, region, x, y)));
      gap.net_mm = std::fmax(gap.net_mm, std::fabs(net_at(nd, region, x, y) - net_at(nf_mm, region, x, y)));
    }
  return gap;
}

}  // namespace

TEST_GROUP(HeightFieldFit){};

TEST(HeightFieldFit, ReproducesABilinearSurfaceExactly) {
  // z = a + bx + cy + dxy lies in the span of the bicubic patch and of the cubic net.
  auto z = [](int32_t x_nm, int32_t y_nm) {
    const double x = x_nm * 1e-6, y = y_nm * 1e-6;
    return static_cast<int32_t>(std::lround((5 + 0.05 * x - 0.04 * y + 0.0004 * x * y) * 1e6));
  };
  DoubleBezier bezier;
  DoubleNet net;
  bezier.begin(kTable);
  net.begin(kTable);
  for (int32_t y = 0; y <= 200; y += 10)
    for (int32_t x = 0; x <= 200; x += 10) {
      bezier.add(x * 1000000, y * 1000000, z(x * 1000000, y * 1000000));
      net.add(x * 1000000, y * 1000000, z(x * 1000000, y * 1000000));
    }
  double pb[4][4], pn[5][5];
  DoubleBezier::Workspace wb;
  DoubleNet::Workspace wn;
  CHECK(dg::Status::kOk == bezier.solve(pb, wb));
  CHECK(dg::Status::kOk == net.solve(pn, wn));
  for (double y = 3; y < 200; y += 17)
    for (double x = 1; x < 200; x += 13) {
      const double expected = 5 + 0.05 * x - 0.04 * y + 0.0004 * x * y;
      DOUBLES_EQUAL(expected, bezier_at(pb, kTable, x, y), 1e-9);
      DOUBLES_EQUAL(expected, net_at(pn, kTable, x, y), 1e-9);
    }
}

TEST(HeightFieldFit, FixedPointMatchesDoubleWithinOneMicrometreOnA200mmTable) {
  const Gap gap = fixed_against_double(kTable, 1, [](double x, double y) {
    return dome_z_nm(static_cast<int32_t>(x * 1e6), static_cast<int32_t>(y * 1e6)) * 1e-6;
  });
  LONGS_EQUAL(201u * 201u, gap.points);
  CHECK_TEXT(gap.bezier_mm < 1e-4, "Bezier: fixed point more than 0.1 um from double");
  CHECK_TEXT(gap.net_mm < 1e-4, "net: fixed point more than 0.1 um from double");
}

TEST(HeightFieldFit, FixedPointMatchesDoubleOnTiltedPartsCoarseGridsAndShortLines) {
  // What drifted by micrometres while basis values were rounded to 2^-16 before their products:
  // a part tilted to 120 mm over the table, a 120 mm bump scanned at 5 mm (41 x 41 points, each
  // basis value repeated on every line), and 10 mm lines climbing 120 mm along y.
  struct Case {
    const char* name;
    FitRegion region;
    double step_mm;
    double (*z_mm)(double, double);
  } cases[] = {
      {"tilted 0.6 along x", kTable, 1, [](double x, double) { return 0.6 * x; }},
      {"tilted 0.4 x + 0.2 y", kTable, 2, [](double x, double y) { return 0.4 * x + 0.2 * y; }},
      {"120 mm bump at 5 mm", kTable, 5,
       [](double x, double y) { return 120 * std::exp(-((x - 100) * (x - 100) + (y - 100) * (y - 100)) / 5000); }},
      {"waves of 120 mm", kTable, 2, [](double x, double y) { return 60 + 60 * std::sin(x / 40) * std::cos(y / 50); }},
      {"10 mm lines up a 120 mm slope", FitRegion{0, 10000000, 0, 200000000}, 0.5, [](double, double y) { return 0.6 * y; }},
  };
  for (const Case& c : cases) {
    const Gap gap = fixed_against_double(c.region, c.step_mm, c.z_mm);
    CHECK_TEXT(gap.bezier_mm < 2.5e-4, c.name);
    CHECK_TEXT(gap.net_mm < 2.5e-4, c.name);
  }
}

TEST(HeightFieldFit, PointsOnOneLineLeaveThePatchUndetermined) {
  FixedBezier fit;
  fit.begin(kTable);
  for (int32_t x = 0; x <= 200; ++x) fit.add(x * 1000000, 50000000, 1000000 + x * 1000);
  int32_t p[4][4];
  static FixedBezier::Workspace work;
  CHECK(dg::Status::kInvalidArgument == fit.solve(p, work));
}

TEST(HeightFieldFit, FewerPointsThanUnknownsIsNotReady) {
  DoubleNet fit;
  fit.begin(kTable);
  for (int i = 0; i < 24; ++i) fit.add(i * 8000000, (i % 5) * 40000000, 0);
  double p[5][5];
  DoubleNet::Workspace work;
  CHECK(dg::Status::kNotReady == fit.solve(p, work));
}

TEST(HeightFieldFit, PointsOutsideTheRegionAreCountedNotUsed) {
  FixedBezier fit;
  fit.begin(kTable);
  CHECK(dg::Status::kInvalidArgument == fit.add(-1, 0, 0));
  CHECK(dg::Status::kInvalidArgument == fit.add(0, 200000001, 0));
  CHECK(dg::Status::kOk == fit.add(0, 0, 0));
  CHECK(dg::Status::kOverflow == fit.add(1, 1, 200000000));  // 200 mm above the first point
  LONGS_EQUAL(1u, fit.count());
  LONGS_EQUAL(3u, fit.rejected());
}

// The streaming height-field fits: exact reproduction, fixed point against double, degenerate data.
#include "common/fit/height_field_fit.h"

#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <new>
#include <random>
#include <vector>

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

namespace {

// The least-squares control heights (mm) of `Kind` over the region, from normal equations built
// point by point out of the kind's own basis functions: what the block moments must reproduce.
template <typename Kind>
void direct_least_squares(const FitRegion& r, const std::vector<std::array<int32_t, 3>>& points,
                          double (&heights)[Kind::kSide][Kind::kSide]) {
  constexpr int kSide = Kind::kSide, kN = kSide * kSide;
  std::vector<double> matrix(packed_size(kN), 0.0), rhs(kN, 0.0), inverse_d(kN);
  for (const auto& p : points) {
    const double u = (static_cast<double>(p[0]) - r.x_min_nm) / (static_cast<double>(r.x_max_nm) - r.x_min_nm);
    const double v = (static_cast<double>(p[1]) - r.y_min_nm) / (static_cast<double>(r.y_max_nm) - r.y_min_nm);
    double bu[4], bv[4];
    int su = 0, sv = 0;
    Kind::template basis<FloatingPolicy<double>>(u, bu, su);
    Kind::template basis<FloatingPolicy<double>>(v, bv, sv);
    double c[kN] = {};
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) c[(su + i) * kSide + sv + j] = bu[i] * bv[j];
    for (int a = 0; a < kN; ++a) {
      rhs[a] += c[a] * p[2] * 1e-6;
      for (int b = 0; b <= a; ++b) matrix[packed_index(a, b)] += c[a] * c[b];
    }
  }
  CHECK(dg::Status::kOk == ldlt_factor(matrix.data(), kN, inverse_d.data(), 1e-12));
  ldlt_solve(matrix.data(), inverse_d.data(), kN, rhs.data());
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j) heights[i][j] = rhs[i * kSide + j];
}

// Scattered points with heights of a rough surface (not in any fit's span), in nm.
std::vector<std::array<int32_t, 3>> scattered_points(const FitRegion& r, int count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<std::array<int32_t, 3>> points;
  for (int k = 0; k < count; ++k) {
    const double u = unit(random), v = unit(random);
    const double z_mm = 20 + 15 * std::sin(7 * u) * std::cos(5 * v) + 3 * u * v * v + 0.01 * unit(random);
    points.push_back({static_cast<int32_t>(r.x_min_nm + u * (r.x_max_nm - r.x_min_nm)),
                      static_cast<int32_t>(r.y_min_nm + v * (r.y_max_nm - r.y_min_nm)),
                      static_cast<int32_t>(std::lround(z_mm * 1e6))});
  }
  return points;
}

template <int kSide>
double largest_difference(const double (&a)[kSide][kSide], const double (&b)[kSide][kSide]) {
  double largest = 0;
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j) largest = std::fmax(largest, std::fabs(a[i][j] - b[i][j]));
  return largest;
}

}  // namespace

TEST(HeightFieldFit, BlockMomentsGiveTheLeastSquaresFitOfTheKindsOwnBasis) {
  const FitRegion region{-30000000, 170000000, 5000000, 125000000};
  const auto points = scattered_points(region, 3000, 11);
  DoubleBezier bezier;
  DoubleNet net;
  // A 7 x 7 net has four spans a side: 16 blocks, each a different part of the sums.
  HeightFieldFit<FloatingPolicy<double>, UniformCubicBasis<7>> wide_net;
  bezier.begin(region);
  net.begin(region);
  wide_net.begin(region);
  for (const auto& p : points) {
    bezier.add(p[0], p[1], p[2]);
    net.add(p[0], p[1], p[2]);
    wide_net.add(p[0], p[1], p[2]);
  }
  double pb[4][4], pn[5][5], pw[7][7], qb[4][4], qn[5][5], qw[7][7];
  static DoubleBezier::Workspace wb;
  static DoubleNet::Workspace wn;
  static decltype(wide_net)::Workspace ww;
  CHECK(dg::Status::kOk == bezier.solve(pb, wb));
  CHECK(dg::Status::kOk == net.solve(pn, wn));
  CHECK(dg::Status::kOk == wide_net.solve(pw, ww));
  direct_least_squares<BezierBasis>(region, points, qb);
  direct_least_squares<UniformCubicBasis<5>>(region, points, qn);
  direct_least_squares<UniformCubicBasis<7>>(region, points, qw);
  DOUBLES_EQUAL(0, largest_difference(pb, qb), 1e-7);
  DOUBLES_EQUAL(0, largest_difference(pn, qn), 1e-7);
  DOUBLES_EQUAL(0, largest_difference(pw, qw), 1e-7);
}

TEST(HeightFieldFit, APatchSolvedFromTheNetsBlocksIsThePatchsOwnFit) {
  // The device keeps one set of sums, cut as the net's spans, and solves its patch from them.
  const FitRegion region{0, 120000000, 0, 90000000};
  const auto points = scattered_points(region, 2000, 5);
  BlockMoments<FloatingPolicy<double>, 2> double_blocks;
  BlockMoments<FixedPolicy<15>, 2> fixed_blocks;
  DoubleBezier double_patch;
  FixedBezier fixed_patch;
  double_blocks.begin(region);
  fixed_blocks.begin(region);
  double_patch.begin(region);
  fixed_patch.begin(region);
  for (const auto& p : points) {
    double_blocks.add(p[0], p[1], p[2]);
    fixed_blocks.add(p[0], p[1], p[2]);
    double_patch.add(p[0], p[1], p[2]);
    fixed_patch.add(p[0], p[1], p[2]);
  }
  double from_blocks[4][4], own[4][4];
  int32_t fixed_from_blocks[4][4], fixed_own[4][4];
  double fixed_from_blocks_mm[4][4], fixed_own_mm[4][4];
  static DoubleBezier::Workspace work;
  static FixedBezier::Workspace fixed_work;
  CHECK(dg::Status::kOk == solve_height_field<BezierBasis>(double_blocks, from_blocks, work));
  CHECK(dg::Status::kOk == double_patch.solve(own, work));
  DOUBLES_EQUAL(0, largest_difference(from_blocks, own), 1e-10);
  CHECK(dg::Status::kOk == solve_height_field<BezierBasis>(fixed_blocks, fixed_from_blocks, fixed_work));
  CHECK(dg::Status::kOk == fixed_patch.solve(fixed_own, fixed_work));
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      fixed_from_blocks_mm[i][j] = fixed_from_blocks[i][j] * 1e-6;
      fixed_own_mm[i][j] = fixed_own[i][j] * 1e-6;
    }
  double largest_mm = 0;
  for (double y = 0; y <= 90; y += 2.5)
    for (double x = 0; x <= 120; x += 2.5) {
      const double z = bezier_at(own, region, x, y);
      largest_mm = std::fmax(largest_mm, std::fabs(bezier_at(fixed_from_blocks_mm, region, x, y) - z));
      largest_mm = std::fmax(largest_mm, std::fabs(bezier_at(fixed_own_mm, region, x, y) - z));
    }
  CHECK(largest_mm < 2e-5);
}

TEST(HeightFieldFit, TheFixedPointFitDoesNotDependOnTheOrderOfThePoints) {
  // Integer sums: rows, columns, short lines or any order give the same control heights to the
  // nanometre, and the same work a point.
  const FitRegion region{0, 200000000, 0, 200000000};
  auto points = scattered_points(region, 1500, 3);
  FixedNet in_order, reversed, shuffled;
  in_order.begin(region);
  reversed.begin(region);
  shuffled.begin(region);
  // The first point sets the reference height; keep it first in every order.
  for (const auto& p : points) in_order.add(p[0], p[1], p[2]);
  reversed.add(points[0][0], points[0][1], points[0][2]);
  for (size_t k = points.size() - 1; k >= 1; --k) reversed.add(points[k][0], points[k][1], points[k][2]);
  std::shuffle(points.begin() + 1, points.end(), std::mt19937(9));
  for (const auto& p : points) shuffled.add(p[0], p[1], p[2]);
  int32_t a[5][5], b[5][5], c[5][5];
  static FixedNet::Workspace work;
  CHECK(dg::Status::kOk == in_order.solve(a, work));
  CHECK(dg::Status::kOk == reversed.solve(b, work));
  CHECK(dg::Status::kOk == shuffled.solve(c, work));
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) {
      LONGS_EQUAL(a[i][j], b[i][j]);
      LONGS_EQUAL(a[i][j], c[i][j]);
    }
}

TEST(HeightFieldFit, TheFixedPointSumsHoldTheMostPointsAndHeightsTheyAccept) {
  // 2^20 points 134 mm above the first, half of them on the corner the four blocks share (where
  // one basis value of each block is 1 and a sum grows fastest), the rest on the other nodes of a
  // 25 mm grid: the largest sums and their conversion run at their bound (a height moment kept
  // to 2^-15 nm instead of 2^-12 overflows here), and both fits must still be the double ones.
  const FitRegion region{0, 100000000, 0, 100000000};
  using Fixed = FixedPolicy<15>;
  const int32_t high = Fixed::kMaxValueNm;
  BlockMoments<Fixed, 2> fixed_blocks;
  BlockMoments<FloatingPolicy<double>, 2> double_blocks;
  fixed_blocks.begin(region);
  double_blocks.begin(region);
  auto add = [&](int32_t x, int32_t y, int32_t z) {
    CHECK(dg::Status::kOk == fixed_blocks.add(x, y, z));
    double_blocks.add(x, y, z);
  };
  add(0, 0, 0);
  for (int32_t j = 0; j <= 4; ++j)
    for (int32_t i = 0; i <= 4; ++i)
      for (uint32_t copy = 0; copy < Fixed::kMaxPoints / 48 && !(i == 2 && j == 2); ++copy)
        add(i * 25000000, j * 25000000, high - (i + j) * 1000000);
  while (fixed_blocks.count() < Fixed::kMaxPoints) add(50000000, 50000000, high);
  CHECK(dg::Status::kOverflow == fixed_blocks.add(0, 0, 0));
  int32_t fixed_patch[4][4], fixed_net[5][5];
  double double_patch[4][4], double_net[5][5], fixed_patch_mm[4][4], fixed_net_mm[5][5];
  static HeightFieldWorkspace<Fixed, UniformCubicBasis<5>> fixed_work;
  static HeightFieldWorkspace<FloatingPolicy<double>, UniformCubicBasis<5>> double_work;
  static HeightFieldWorkspace<Fixed, BezierBasis> fixed_patch_work;
  static HeightFieldWorkspace<FloatingPolicy<double>, BezierBasis> double_patch_work;
  CHECK(dg::Status::kOk == solve_height_field<BezierBasis>(fixed_blocks, fixed_patch, fixed_patch_work));
  CHECK(dg::Status::kOk == solve_height_field<BezierBasis>(double_blocks, double_patch, double_patch_work));
  CHECK(dg::Status::kOk == solve_height_field<UniformCubicBasis<5>>(fixed_blocks, fixed_net, fixed_work));
  CHECK(dg::Status::kOk == solve_height_field<UniformCubicBasis<5>>(double_blocks, double_net, double_work));
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) fixed_patch_mm[i][j] = fixed_patch[i][j] * 1e-6;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) fixed_net_mm[i][j] = fixed_net[i][j] * 1e-6;
  for (double y = 0; y <= 100; y += 5)
    for (double x = 0; x <= 100; x += 5) {
      DOUBLES_EQUAL(bezier_at(double_patch, region, x, y), bezier_at(fixed_patch_mm, region, x, y), 1e-4);
      DOUBLES_EQUAL(net_at(double_net, region, x, y), net_at(fixed_net_mm, region, x, y), 1e-4);
    }
}

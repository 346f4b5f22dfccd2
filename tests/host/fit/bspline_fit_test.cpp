// Least-squares B-spline surfaces: exact reproduction, convergence, parameterizations, weights, errors.
#include "host/fit/bspline_fit.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <random>

#include "host/geometry/closest_point.h"
#include "host/fit/fit_error.h"
#include "host/geometry/vec3.h"
#include "host/fit/orthogonal_distances.h"
#include "tests/support/scattered_cloud.h"

using namespace dg::host;

namespace {

PointCloud grid(int nx, int ny, double step, double (*z)(double, double), bool serpentine = false) {
  PointCloud c;
  c.line = std::vector<uint32_t>();
  for (int j = 0; j < ny; ++j) {
    for (int k = 0; k < nx; ++k) {
      const int i = serpentine && (j % 2) ? nx - 1 - k : k;
      const double x = i * step, y = j * step;
      c.points.push_back({x, y, z(x, y)});
      c.line->push_back(static_cast<uint32_t>(j));
    }
  }
  return c;
}

double wave(double x, double y) { return 2.0 + std::sin(x / 7.0) * std::cos(y / 9.0); }

LsqSpec cubic(int nu, int nv) {
  LsqSpec s;
  s.knots_u = clamped_uniform_knots(nu, 3);
  s.knots_v = clamped_uniform_knots(nv, 3);
  return s;
}

double max_vertical_error(const BSplineSurface& s, double (*z)(double, double)) {
  double worst = 0;
  for (double u = 0; u <= 1.0; u += 1.0 / 97) {
    for (double v = 0; v <= 1.0; v += 1.0 / 89) {
      const Point3 q = s.evaluate(u, v);
      worst = std::fmax(worst, std::fabs(q.z - z(q.x, q.y)));
    }
  }
  return worst;
}

}  // namespace

TEST_GROUP(BSplineFit){};

TEST(BSplineFit, ReproducesABilinearSurfaceFromScatteredPointsToRounding) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> along(0.0, 50.0);
  PointCloud c;
  for (int i = 0; i < 2000; ++i) {
    const double x = along(rng), y = along(rng) * 0.8;
    c.points.push_back({x, y, 5 + 0.05 * x - 0.04 * y + 0.004 * x * y});
  }
  const Parameters p = parameterize(c, Parameterization::kTableXy);
  const BSplineSurface s = fit_least_squares(c.points, p, nullptr, cubic(7, 5));
  for (const double d : orthogonal_distances(s, c.points, p)) DOUBLES_EQUAL(0.0, d, 1e-9);
}

TEST(BSplineFit, CubicErrorFallsAboutSixteenfoldWhenSpansHalve) {
  const PointCloud c = grid(161, 161, 0.5, wave);
  const Parameters p = parameterize(c, Parameterization::kTableXy);
  double previous = 0;
  for (int spans : {4, 8, 16, 32}) {
    const BSplineSurface s = fit_least_squares(c.points, p, nullptr, cubic(spans + 3, spans + 3));
    const double error = max_vertical_error(s, wave);
    if (previous > 0) CHECK_TEXT(previous / error > 10.0, "convergence slower than third order");
    previous = error;
  }
  CHECK(previous < 1e-4);
}

TEST(BSplineFit, EveryParameterizationFitsASerpentineGrid) {
  const PointCloud c = grid(41, 31, 1.0, wave, true);
  for (auto kind : {Parameterization::kUniform, Parameterization::kChordLength, Parameterization::kCentripetal,
                    Parameterization::kTableXy}) {
    const Parameters p = parameterize(c, kind);
    // The serpentine's reversed lines are turned around: u grows with x on every line.
    CHECK(p.uv[40].u > p.uv[39].u);  // line 0, forwards
    CHECK(p.uv[41].u > p.uv[42].u);  // line 1, recorded backwards
    const BSplineSurface s = fit_least_squares(c.points, p, nullptr, cubic(10, 10));
    double worst = 0;
    for (double d : orthogonal_distances(s, c.points, p)) worst = std::fmax(worst, std::fabs(d));
    CHECK_TEXT(worst < 2e-3, parameterization_name(kind));
  }
}

TEST(BSplineFit, ChordParametersFollowEquation6) {
  PointCloud c;
  c.line = std::vector<uint32_t>{0, 0, 0, 1, 1, 1};
  c.points = {{0, 0, 0}, {1, 0, 0}, {4, 0, 0}, {0, 2, 0}, {1, 2, 0}, {4, 2, 0}};
  const Parameters chord = parameterize(c, Parameterization::kChordLength);
  DOUBLES_EQUAL(0.25, chord.uv[1].u, 1e-15);
  const Parameters centripetal = parameterize(c, Parameterization::kCentripetal);
  DOUBLES_EQUAL(1.0 / (1.0 + std::sqrt(3.0)), centripetal.uv[1].u, 1e-15);
  DOUBLES_EQUAL(1.0, centripetal.uv[5].v, 0.0);
}

TEST(BSplineFit, SigmaWeightsSilenceAnUncertainPoint) {
  PointCloud c = grid(21, 21, 1.0, [](double, double) { return 1.0; });
  c.points[220].z = 5.0;  // a wild point in the middle
  const Parameters p = parameterize(c, Parameterization::kTableXy);
  std::vector<double> w(c.points.size(), 1.0);
  w[220] = 1e-12;
  const BSplineSurface weighted = fit_least_squares(c.points, p, &w, cubic(6, 6));
  const BSplineSurface plain = fit_least_squares(c.points, p, nullptr, cubic(6, 6));
  DOUBLES_EQUAL(1.0, weighted.evaluate(0.5, 0.5).z, 1e-6);
  CHECK(plain.evaluate(0.5, 0.5).z > 1.05);
}

TEST(BSplineFit, DegenerateInputsAreClearErrors) {
  PointCloud line;
  for (int i = 0; i < 50; ++i) line.points.push_back({i * 1.0, 2 * i * 1.0, 0.1 * i});
  CHECK_THROWS(FitError, parameterize(line, Parameterization::kTableXy));
  line.line = std::vector<uint32_t>(50, 0);
  CHECK_THROWS(FitError, parameterize(line, Parameterization::kChordLength));
  PointCloud no_lines = grid(5, 5, 1.0, wave);
  no_lines.line.reset();
  CHECK_THROWS(FitError, parameterize(no_lines, Parameterization::kCentripetal));
  // 25 points cannot determine 6 x 6 control points.
  const PointCloud small = grid(5, 5, 1.0, wave);
  const Parameters p = parameterize(small, Parameterization::kTableXy);
  CHECK_THROWS(FitError, fit_least_squares(small.points, p, nullptr, cubic(6, 6)));
  // Enough points, but all of them in the left half: the right columns have nothing.
  PointCloud left = grid(41, 41, 1.0, wave);
  for (auto& q : left.points) q.x = q.x < 20 ? q.x : (q.x == 40 ? 40 : q.x * 0.4);
  const Parameters pl = parameterize(left, Parameterization::kTableXy);
  try {
    fit_least_squares(left.points, pl, nullptr, cubic(20, 6));
    FAIL("expected a FitError");
  } catch (const FitError& e) {
    STRCMP_CONTAINS("no point in the support", e.what());
  }
}

TEST(BSplineFit, OrthogonalDistanceToATiltedPlaneIsTheNormalDistance) {
  const PointCloud c = grid(11, 11, 1.0, [](double x, double) { return 0.5 * x; });
  const Parameters p = parameterize(c, Parameterization::kTableXy);
  const BSplineSurface s = fit_least_squares(c.points, p, nullptr, cubic(4, 4));
  const Closest above = closest_point(s, {5.0, 5.0, 2.5 + 1.0}, 0.5, 0.5);
  DOUBLES_EQUAL(1.0 / std::sqrt(1.25), above.distance, 1e-9);  // cos of the slope angle
  const Closest below = closest_point(s, {5.0, 5.0, 2.5 - 1.0}, 0.5, 0.5);
  DOUBLES_EQUAL(-1.0 / std::sqrt(1.25), below.distance, 1e-9);
  CHECK_FALSE(above.on_border);
  CHECK_FALSE(below.on_border);
}

TEST(BSplineFit, AFootClampedToTheDomainIsOnTheBorder) {
  // On the plane's continuation past x = 10 the foot stops at the edge, 5 mm along the plane short
  // of the point; in a corner at both edges.
  const PointCloud c = grid(11, 11, 1.0, [](double x, double) { return 0.5 * x; });
  const Parameters p = parameterize(c, Parameterization::kTableXy);
  const BSplineSurface s = fit_least_squares(c.points, p, nullptr, cubic(4, 4));
  const Closest beyond = closest_point(s, {15.0, 5.0, 7.5}, 0.5, 0.5);
  CHECK(beyond.on_border);
  DOUBLES_EQUAL(10.0, beyond.point.x, 1e-6);
  DOUBLES_EQUAL(5.0 * std::sqrt(1.25), std::fabs(beyond.distance), 1e-6);
  const Closest corner = closest_point(s, {-3.0, -4.0, 0.0}, 0.5, 0.5);
  CHECK(corner.on_border);
  DOUBLES_EQUAL(0.0, corner.point.x, 1e-6);
  DOUBLES_EQUAL(0.0, corner.point.y, 1e-6);
}

// A net whose normal equations cannot fit in memory is refused with the figure, before anything
// large is allocated (a 1000 x 1000 net on a million points died with a bare std::bad_alloc).
TEST(BSplineFit, RefusesANetTooLargeForTheMachinesMemoryWithTheFigure) {
  const int side = 1500;
  std::vector<Point3> points;
  Parameters params;
  points.reserve(static_cast<size_t>(side) * side);
  params.uv.reserve(points.capacity());
  for (int j = 0; j < side; ++j) {
    for (int i = 0; i < side; ++i) {
      points.push_back({1.0 * i, 1.0 * j, 1.0});
      params.uv.push_back({i / (side - 1.0), j / (side - 1.0)});
    }
  }
  LsqSpec spec;
  spec.knots_u = spec.knots_v = clamped_uniform_knots(side, 3);
  try {
    fit_least_squares(points, params, nullptr, spec);
    FAIL("a 1500 x 1500 net was attempted");
  } catch (const FitError& e) {
    STRCMP_CONTAINS("GB for its normal equations", e.what());
  }
}

namespace {

// Restores the machine's thread count after a test that sets it.
struct ThreadCount {
  explicit ThreadCount(const char* n) { setenv("DIGITIZER_THREADS", n, 1); }
  ~ThreadCount() { unsetenv("DIGITIZER_THREADS"); }
};

}  // namespace

TEST(BSplineFit, OneThreadAndFourGiveTheSameNetToTheBit) {
  // 300,000 points: the assembly sums them in four slices, which one thread or four may take.
  const PointCloud c = dg::test::scattered_cloud(300000, 60, 60, 5, 0.002, wave);
  const Parameters p = parameterize(c, Parameterization::kTableXy);
  BSplineSurface one, four;
  std::vector<double> d_one, d_four;
  {
    const ThreadCount threads("1");
    one = fit_least_squares(c.points, p, nullptr, cubic(20, 17));
    d_one = orthogonal_distances(one, c.points, p);
  }
  {
    const ThreadCount threads("4");
    four = fit_least_squares(c.points, p, nullptr, cubic(20, 17));
    d_four = orthogonal_distances(four, c.points, p);
  }
  LONGS_EQUAL(one.control.size(), four.control.size());
  for (size_t k = 0; k < one.control.size(); ++k) {
    CHECK(one.control[k].x == four.control[k].x && one.control[k].y == four.control[k].y &&
          one.control[k].z == four.control[k].z);
  }
  CHECK(d_one == d_four);
  // And the fit is a fit: the noise is what is left.
  double sum_sq = 0;
  for (double d : d_one) sum_sq += d * d;
  DOUBLES_EQUAL(0.002, std::sqrt(sum_sq / static_cast<double>(d_one.size())), 0.0002);
}

TEST(BSplineFit, RefitsWithoutEachFoldFromOnePassAreTheRefitsOfTheRemainingPoints) {
  // The one-pass refits against fitting each fold's remaining points afresh, and the same with a
  // pass per fold (no memory for one); a fold whose remaining points leave a control point free
  // says so and the others are still fitted.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> along(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.003);
  PointCloud c;
  for (int k = 0; k < 6000; ++k) {
    const double x = 40 * along(rng), y = 30 * along(rng);
    c.points.push_back({x, y, 2 + 0.01 * x * y / 30 + std::sin(x / 7) + noise(rng)});
  }
  const Parameters p = parameterize(c, Parameterization::kTableXy);
  std::vector<double> weights(c.points.size());
  for (double& w : weights) w = 0.5 + along(rng);
  std::vector<int> fold(c.points.size());
  for (size_t k = 0; k < fold.size(); ++k) fold[k] = static_cast<int>(k % 4) - 1;  // -1: in every refit
  LsqSpec spec;
  spec.knots_u = clamped_uniform_knots(12, 3);
  spec.knots_v = clamped_uniform_knots(9, 3);
  std::vector<Parameters> kept_params(3, p);
  std::vector<std::unique_ptr<SiteIndex>> indexes;
  std::vector<const SiteIndex*> kept_sites;
  std::vector<BSplineSurface> afresh;
  for (int f = 0; f < 3; ++f) {
    std::vector<Point3> kept;
    std::vector<double> kept_weights;
    kept_params[static_cast<size_t>(f)].uv.clear();
    for (size_t k = 0; k < fold.size(); ++k) {
      if (fold[k] == f) continue;
      kept.push_back(c.points[k]);
      kept_weights.push_back(weights[k]);
      kept_params[static_cast<size_t>(f)].uv.push_back(p.uv[k]);
    }
    indexes.push_back(std::make_unique<SiteIndex>(kept_params[static_cast<size_t>(f)].uv));
    kept_sites.push_back(indexes.back().get());
    afresh.push_back(fit_least_squares(kept, kept_params[static_cast<size_t>(f)], &kept_weights, spec));
  }
  // The whole fit with its refits from the same pass (fit --ctrl): the whole fit's sums are the
  // folds' together.
  const BSplineSurface whole = fit_least_squares(c.points, p, &weights, spec);
  for (size_t budget : {size_t{256} << 20, size_t{0}}) {
    const std::vector<FoldRefit> refits = fit_least_squares_by_folds(c.points, p, &weights, spec, fold, kept_sites, budget);
    const FoldedFit folded = fit_least_squares_with_folds(c.points, p, &weights, spec, fold, kept_sites, budget);
    LONGS_EQUAL(3, refits.size());
    LONGS_EQUAL(3, folded.refits.size());
    for (size_t f = 0; f < 3; ++f) {
      STRCMP_EQUAL("", refits[f].error.c_str());
      STRCMP_EQUAL("", folded.refits[f].error.c_str());
      LONGS_EQUAL(afresh[f].control.size(), refits[f].surface.control.size());
      LONGS_EQUAL(afresh[f].control.size(), folded.refits[f].surface.control.size());
      for (size_t k = 0; k < afresh[f].control.size(); ++k) {
        DOUBLES_EQUAL(afresh[f].control[k].z, refits[f].surface.control[k].z, 1e-9);
        DOUBLES_EQUAL(afresh[f].control[k].z, folded.refits[f].surface.control[k].z, 1e-9);
      }
    }
    CHECK(folded.fit.weighted);
    LONGS_EQUAL(whole.control.size(), folded.fit.surface.control.size());
    for (size_t k = 0; k < whole.control.size(); ++k) DOUBLES_EQUAL(whole.control[k].z, folded.fit.surface.control[k].z, 1e-9);
  }
  // Fold 1 now holds every point with x < 10 mm: without them nothing determines the net's left columns.
  for (size_t k = 0; k < fold.size(); ++k) {
    if (c.points[k].x < 10 && fold[k] != 1) fold[k] = 1;
  }
  kept_params[1].uv.clear();
  for (size_t k = 0; k < fold.size(); ++k) {
    if (fold[k] != 1) kept_params[1].uv.push_back(p.uv[k]);
  }
  indexes[1] = std::make_unique<SiteIndex>(kept_params[1].uv);
  kept_sites[1] = indexes[1].get();
  const std::vector<FoldRefit> refits = fit_least_squares_by_folds(c.points, p, &weights, spec, fold, kept_sites);
  STRCMP_CONTAINS("control point", refits[1].error.c_str());
  CHECK(refits[1].surface.control.empty());
  STRCMP_EQUAL("", refits[0].error.c_str());
  STRCMP_EQUAL("", refits[2].error.c_str());
}

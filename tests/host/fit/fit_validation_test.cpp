// Checks between the samples: hold-out refits and neighbour ranges, the same on any number of
// threads and with or without the tolerance loop's fold indexes; a bump no neighbour confirms is caught.
#include "host/fit/fit_validation.h"
#include "host/fit/knot_support.h"

#include <CppUTest/TestHarness.h>

#include <array>

#include <cmath>
#include <cstdlib>
#include <random>

using namespace dg::host;

namespace {

double bowl(double x, double y) { return 3.0 + 0.002 * ((x - 25) * (x - 25) + (y - 20) * (y - 20)) + 0.2 * std::sin(x / 6.0); }

// Scan lines 1 mm apart with points every 0.25 mm, or (lines = false) the same count scattered.
PointCloud cloud(bool lines, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.002);
  std::uniform_real_distribution<double> x_along(0.0, 50.0), y_along(0.0, 40.0);
  PointCloud c;
  if (lines) c.line.emplace();
  for (int j = 0; j <= 40; ++j) {
    for (int i = 0; i <= 200; ++i) {
      const double x = lines ? i * 0.25 : x_along(rng), y = lines ? j * 1.0 : y_along(rng);
      c.points.push_back({x, y, bowl(x, y) + noise(rng)});
      if (lines) c.line->push_back(static_cast<uint32_t>(j));
    }
  }
  return c;
}

BSplineSurface fit(const PointCloud& c, const Parameters& p, int nu, int nv) {
  LsqSpec spec;
  spec.knots_u = clamped_uniform_knots(nu, 3);
  spec.knots_v = clamped_uniform_knots(nv, 3);
  return fit_least_squares(c.points, p, nullptr, spec);
}

FitValidation validate_on(const char* threads, const PointCloud& c, const Parameters& p, const BSplineSurface& s,
                          const FoldSupport* support) {
  setenv("DIGITIZER_THREADS", threads, 1);
  const FitValidation v = validate_fit(c, p, nullptr, s, ValidationOptions{0.02, 5, 3, false}, support);
  unsetenv("DIGITIZER_THREADS");
  return v;
}

void check_same(const FitValidation& a, const FitValidation& b) {
  CHECK(a.passed == b.passed);
  STRCMP_EQUAL(a.problem.c_str(), b.problem.c_str());
  LONGS_EQUAL(a.held_out_points, b.held_out_points);
  CHECK(a.held_out_rms_mm == b.held_out_rms_mm);
  CHECK(a.held_out_max_mm == b.held_out_max_mm);
  LONGS_EQUAL(a.neighbour_checks, b.neighbour_checks);
  CHECK(a.range_excess_max_mm == b.range_excess_max_mm);
  CHECK(a.range_worst.x == b.range_worst.x && a.range_worst.y == b.range_worst.y && a.range_worst.z == b.range_worst.z);
}

}  // namespace

TEST_GROUP(FitValidation){};

TEST(FitValidation, OneThreadAndFourGiveTheSameFiguresForLinesAndScatteredPoints) {
  for (bool lines : {true, false}) {
    const PointCloud c = cloud(lines, 3);
    const Parameters p = parameterize(c, Parameterization::kTableXy);
    const BSplineSurface s = fit(c, p, 14, 12);
    const FitValidation one = validate_on("1", c, p, s, nullptr), four = validate_on("4", c, p, s, nullptr);
    CHECK(one.checked && one.passed);
    CHECK(one.folds_of_lines == lines);
    CHECK(one.held_out_points > 7000);
    CHECK(one.neighbour_checks > 20000);
    check_same(one, four);
  }
}

TEST(FitValidation, TheToleranceLoopsFoldIndexesGiveTheSameFiguresAsFoldsBuiltAfresh) {
  for (bool lines : {true, false}) {
    const PointCloud c = cloud(lines, 4);
    const Parameters p = parameterize(c, Parameterization::kTableXy);
    const BSplineSurface s = fit(c, p, 12, 10);
    const FoldSupport support(c, p, 5);
    check_same(validate_on("2", c, p, s, nullptr), validate_on("2", c, p, s, &support));
    // Points without lines had their neighbours found beside the fit, each point's four nearest.
    CHECK((support.plane_neighbours() == nullptr) == lines);
    if (!lines) LONGS_EQUAL(5, support.plane_neighbours()->k);
  }
}

TEST(FitValidation, ABumpOnOneLineThatTheOthersDoNotShowIsCaught) {
  // A fine net follows a 0.3 mm bump on one scan line; the surface fitted without that line does
  // not predict it, so the hold-out check names it. The same scan without the bump passes.
  PointCloud c = cloud(true, 5);
  const Parameters p = parameterize(c, Parameterization::kTableXy);
  const FitValidation coarse = validate_on("2", c, p, fit(c, p, 14, 12), nullptr);
  CHECK(coarse.passed);
  for (size_t k = 0; k < c.points.size(); ++k) {
    if ((*c.line)[k] == 20 && std::fabs(c.points[k].x - 25.0) < 0.6) c.points[k].z += 0.3;
  }
  const FitValidation bumped = validate_on("2", c, p, fit(c, p, 60, 20), nullptr);
  CHECK_FALSE(bumped.passed);
  STRCMP_CONTAINS("hold-out check", bumped.problem.c_str());
  DOUBLES_EQUAL(25.0, bumped.held_out_worst.x, 0.6);
  DOUBLES_EQUAL(20.0, bumped.held_out_worst.y, 1e-9);
  CHECK(bumped.held_out_max_mm > 0.25);
}

TEST(FitValidation, PlacesTheCurvatureBoundCertifiesGiveTheFiguresOfEvaluatingEveryPlace) {
  // Certifying places from the curvature bound may spare their evaluation but not change a figure:
  // measuring (no tolerance), judging (a tolerance), and a net that rings between the samples (a
  // 60 x 20 net over a one-line bump) give what evaluating every place gives.
  for (bool lines : {true, false}) {
    PointCloud c = cloud(lines, 6);
    const Parameters p = parameterize(c, Parameterization::kTableXy);
    for (size_t k = 0; k < c.points.size(); k += 97) c.points[k].z += 0.05;  // scattered spikes to leave the range at
    for (int net : {12, 60}) {
      const BSplineSurface s = fit(c, p, net, net == 60 ? 20 : 10);
      for (double tolerance : {0.0, 0.02}) {
        ValidationOptions certified{tolerance, 5, 3, false};
        ValidationOptions every = certified;
        every.certify_by_curvature = false;
        const FitValidation a = validate_fit(c, p, nullptr, s, certified), b = validate_fit(c, p, nullptr, s, every);
        check_same(a, b);
        CHECK(a.neighbour_checks > 20000);
        if (tolerance == 0.0) CHECK(a.range_excess_max_mm > 0.01);  // the spikes: there is a worst to find
      }
    }
  }
}

TEST(FitValidation, TheSupportsSitesOfEveryPointAreThoseOfSortingThemAlone) {
  // The tolerance loop's whole-set index takes them instead of sorting every parameter again; the
  // first and last scan lines, in no fold, are among them.
  for (bool lines : {true, false}) {
    const PointCloud c = cloud(lines, 9);
    const Parameters p = parameterize(c, Parameterization::kTableXy);
    const FoldSupport support(c, p, 5);
    const SiteIndex alone(p.uv, false);
    for (bool along_u : {true, false}) {
      const std::vector<double>& expected = along_u ? alone.sites_u() : alone.sites_v();
      const std::vector<double>& got = along_u ? support.all_sites_u() : support.all_sites_v();
      CHECK(expected.size() > 10);
      LONGS_EQUAL(expected.size(), got.size());
      for (size_t k = 0; k < got.size(); ++k) CHECK(expected[k] == got[k]);
    }
  }
}

TEST(FitValidation, EachFoldsIndexHoldsItsRemainingPointsAndTheirSitesToTheBit) {
  // The fold indexes merge sorted groups instead of sorting each fold: the same sites as sorting.
  for (bool lines : {true, false}) {
    const PointCloud c = cloud(lines, 8);
    const Parameters p = parameterize(c, Parameterization::kTableXy);
    const FoldSupport support(c, p, 5);
    const std::vector<int> fold = validation_folds(c, 5);
    for (int f = 0; f < 5; ++f) {
      std::vector<UV> kept;
      for (size_t k = 0; k < fold.size(); ++k) {
        if (fold[k] != f) kept.push_back(p.uv[k]);
      }
      const double merge = site_merge_distance(kept.size());
      for (bool along_u : {true, false}) {
        const std::vector<double> expected = distinct_sites(kept, along_u, merge);
        const std::vector<double>& got = along_u ? support.kept_sites(f).sites_u() : support.kept_sites(f).sites_v();
        LONGS_EQUAL(expected.size(), got.size());
        for (size_t k = 0; k < got.size(); ++k) CHECK(expected[k] == got[k]);
      }
      // Its buckets hold those points and no other.
      std::vector<size_t> visited;
      support.kept_sites(f).visit(0.0, 1.0, 0.0, 1.0, [&](size_t k) {
        visited.push_back(k);
        return true;
      });
      LONGS_EQUAL(kept.size(), visited.size());
      for (size_t k : visited) CHECK(fold[k] != f);
      // In the order the fold's own bucketing gives (the support takes it out of every point's).
      const SiteIndex own(p.uv, fold, f, {}, {});
      for (const std::array<double, 4>& box : {std::array<double, 4>{0, 1, 0, 1}, std::array<double, 4>{0.2, 0.45, 0.6, 0.7}}) {
        std::vector<size_t> in_support, in_own;
        support.kept_sites(f).visit(box[0], box[1], box[2], box[3], [&](size_t k) { in_support.push_back(k); return true; });
        own.visit(box[0], box[1], box[2], box[3], [&](size_t k) { in_own.push_back(k); return true; });
        CHECK(in_support == in_own);
      }
    }
  }
}

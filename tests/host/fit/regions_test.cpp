// Regions between creases: the dome comes back as trimmed faces within the tolerance of the true part
// everywhere inside the scan, and a smooth part stays one surface, scanned or scattered.
#include <CppUTest/TestHarness.h>

#include <cmath>
#include <cstdio>

#include "host/fit/regions.h"
#include "tests/support/part_scan.h"
#include "tests/support/scattered_cloud.h"

using namespace dg::host;

namespace {

RegionFit fit_scan(const dg::test::PartScan& s, unsigned seed, double tolerance_mm) {
  RegionOptions o;
  o.tolerance.tolerance_mm = tolerance_mm;
  return fit_regions(dg::test::scan_part(s, seed), nullptr, o);
}

}  // namespace

TEST_GROUP(Regions){};

TEST(Regions, TheDomeComesBackAsTrimmedFacesWithinTheToleranceOfTheTruePartEverywhere) {
  dg::test::PartScan s;
  s.kind = dg::sim::PartKind::kDome;
  s.sigma_um = 5;
  const double tolerance = 0.025;
  const RegionFit r = fit_scan(s, 3, tolerance);
  CHECK(r.kept);
  // The cap and the base plate's four corners.
  CHECK(r.regions >= 2);
  dg::host::Point3 where;
  int uncovered = 0;
  const double truth = dg::test::max_error_against_part(r.faces, s, 4, &where, &uncovered);
  LONGS_EQUAL(0, uncovered);
  CHECK(truth <= tolerance);
}

TEST(Regions, AKeptDomeIsWithinTheToleranceOfTheTruePartAtEveryNoiseAndTolerance) {
  // Kept or refused with a reason, never kept and wrong.
  int kept = 0;
  for (double sigma : {1.0, 2.0, 5.0}) {
    for (double f : {2.0, 5.0, 25.0}) {
      for (unsigned seed : {3u, 7u}) {
        dg::test::PartScan s;
        s.sigma_um = sigma;
        const double tolerance = f * sigma * 1e-3;
        const RegionFit r = fit_scan(s, seed, tolerance);
        CHECK(r.regions >= 2);
        if (!r.kept) {
          CHECK(!r.reason.empty());
          continue;
        }
        ++kept;
        int uncovered = 0;
        dg::host::Point3 where;
        const double truth = dg::test::max_error_against_part(r.faces, s, 4, &where, &uncovered);
        if (truth > tolerance) {
          std::printf("\nsigma %.0f tol %.4f seed %u: true %.4f at (%.2f, %.2f)\n", sigma, tolerance, seed, truth, where.x, where.y);
          for (const TrimmedFace& f : r.faces) std::printf("face %d x %d, %zu points, loops %zu\n", f.surface.count_u, f.surface.count_v, f.points, f.loops.size());
        }
        CHECK(truth <= tolerance);
        LONGS_EQUAL(0, uncovered);
      }
    }
  }
  CHECK(kept >= 6);
}

TEST(Regions, ASmoothPartIsOneRegion) {
  for (auto kind : {dg::sim::PartKind::kSaddle, dg::sim::PartKind::kCanister}) {
    for (double sigma : {1.0, 5.0}) {
      dg::test::PartScan s;
      s.kind = kind;
      s.sigma_um = sigma;
      LONGS_EQUAL(1, fit_scan(s, 3, 5 * sigma * 1e-3).regions);
    }
  }
}


// Scattered points (no scan lines) of a smooth part: every window is smooth, yet the links from
// each window's centre to its four nearest leave islands of a dozen points or more among 100,000
// random places (two of them here, each once a "region" of its own).
TEST(Regions, AScatteredCloudOfASmoothPartIsOneRegion) {
  const PointCloud c = dg::test::scattered_cloud(100000, 100, 100, 1, 0.002, [](double x, double y) {
    return 3.0 + 0.002 * ((x - 50) * (x - 50) + (y - 50) * (y - 50)) + 0.3 * std::sin(x / 9.0) * std::sin(y / 11.0);
  });
  RegionOptions o;
  o.tolerance.tolerance_mm = 0.02;
  const RegionFit r = fit_regions(c, nullptr, o);
  LONGS_EQUAL(1, r.regions);
  LONGS_EQUAL(0, r.crease_points);
}

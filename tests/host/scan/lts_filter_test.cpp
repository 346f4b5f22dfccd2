// The LTS filter: spikes found and replaced, inliers kept, grid and scattered neighbourhoods.
#include "host/scan/lts_filter.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <random>
#include <set>
#include <stdexcept>

#include "host/scan/spatial_order.h"
#include "tests/support/scattered_cloud.h"

using namespace dg::host;

namespace {

double bowl(double x, double y) { return 2.0 + 0.003 * ((x - 20) * (x - 20) + (y - 15) * (y - 15)); }

std::vector<Point3> grid_with_spikes(std::set<size_t>& spikes, bool jitter) {
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0.0, 0.002);
  std::uniform_real_distribution<double> shift(-0.3, 0.3);
  std::vector<Point3> p;
  for (int j = 0; j <= 30; ++j)
    for (int i = 0; i <= 40; ++i) {
      const double x = i + (jitter ? shift(rng) : 0.0), y = j + (jitter ? shift(rng) : 0.0);
      p.push_back({x, y, bowl(x, y) + noise(rng)});
    }
  for (size_t k : {100u, 377u, 512u, 800u, 1100u}) {
    p[k].z += (k % 2 ? 0.5 : -0.4);
    spikes.insert(k);
  }
  return p;
}

}  // namespace

TEST_GROUP(LtsFilter){};

TEST(LtsFilter, FindsAndReplacesSpikesOnAGridAndKeepsEveryOtherPoint) {
  std::set<size_t> spikes;
  const std::vector<Point3> p = grid_with_spikes(spikes, false);
  const LtsResult r = lts_filter(p, LtsOptions{});
  CHECK(r.gridded);
  std::set<size_t> found;
  for (const auto& o : r.outliers) found.insert(o.index);
  for (size_t k : spikes) {
    CHECK(found.count(k) == 1);
    DOUBLES_EQUAL(bowl(p[k].x, p[k].y), r.z[k], 0.01);
  }
  LONGS_EQUAL(r.z.size(), p.size());
  size_t changed = 0;
  for (size_t i = 0; i < p.size(); ++i) changed += r.z[i] != p[i].z;
  LONGS_EQUAL(found.size(), changed);
  // 3 sigma flags about 0.3 % of Gaussian points (4 of 1271): a few, never many.
  CHECK_TEXT(found.size() <= spikes.size() + 12, StringFrom(static_cast<long>(found.size())).asCharString());
}

TEST(LtsFilter, ScatteredPointsUseTheNearestNeighbours) {
  std::set<size_t> spikes;
  const std::vector<Point3> p = grid_with_spikes(spikes, true);
  const LtsResult r = lts_filter(p, LtsOptions{});
  CHECK(!r.gridded);
  std::set<size_t> found;
  for (const auto& o : r.outliers) found.insert(o.index);
  for (size_t k : spikes) CHECK(found.count(k) == 1);
}

// Two spikes side by side among scattered points: the whole window's passing over a suspected
// neighbour asks whether the grid's wider window is smooth, and scattered points have none (it
// read past an empty list and crashed, found by the stages fuzzer); they are still both found.
TEST(LtsFilter, ScatteredPointsWithTwoSpikesSideBySideAreBothFound) {
  std::set<size_t> spikes;
  std::vector<Point3> p = grid_with_spikes(spikes, true);
  p[600].z += 0.3, p[601].z -= 0.45;
  spikes.insert(600), spikes.insert(601);
  const LtsResult r = lts_filter(p, LtsOptions{});
  CHECK(!r.gridded);
  std::set<size_t> found;
  for (const auto& o : r.outliers) found.insert(o.index);
  for (size_t k : spikes) CHECK(found.count(k) == 1);
}

TEST(LtsFilter, TheConstantModelIsThePapersTrimmedMeanOf13) {
  // A flat grid with one spike: every 5x5 window's 13 nearest-to-median heights are the flat ones.
  std::vector<Point3> p;
  for (int j = 0; j < 9; ++j)
    for (int i = 0; i < 9; ++i) p.push_back({1.0 * i, 1.0 * j, 1.0});
  p[40].z = 9.0;
  LtsOptions o;
  o.order = 0;
  o.replace_all = true;
  const LtsResult r = lts_filter(p, o);
  for (double z : r.z) DOUBLES_EQUAL(1.0, z, 1e-12);
  CHECK(r.converged);
  LONGS_EQUAL(1, static_cast<long>(r.outliers.size()));
}

TEST(LtsFilter, RejectsAnEvenWindow) {
  LtsOptions o;
  o.window = 4;
  const std::vector<Point3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  CHECK_THROWS(std::invalid_argument, lts_filter(p, o));
}

TEST(LtsFilter, SettlesWhenGaugeQuantisationMakesItAlternate) {
  // The demo's scan: the simulated canister read by a 1 um gauge. Its quantised heights make ties
  // in the trimmed subsets, and one window alternated between two of them for all 50 iterations.
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.001);
  int converged = 0, cases = 0;
  for (double curvature : {0.002, 0.004, 0.006, 0.008}) {
    std::vector<Point3> p;
    for (int j = 0; j <= 30; ++j)
      for (int i = 0; i <= 40; ++i) {
        const double z = 7.0 + curvature * ((i - 20) * (i - 20) + (j - 15) * (j - 15)) + noise(rng);
        p.push_back({1.0 * i, 1.0 * j, std::round(z * 1000.0) / 1000.0});
      }
    const LtsResult r = lts_filter(p, LtsOptions{});
    converged += r.converged;
    ++cases;
    CHECK(r.iterations < 50);
  }
  LONGS_EQUAL(cases, converged);
}

// A single scan line (points on one line in XY) has no area to model a surface on: refused at once
// (it hung: the scattered-point neighbour grid collapsed to a cell of a micrometre).
TEST(LtsFilter, RefusesPointsOnOneLineInXY) {
  std::vector<Point3> p;
  for (int i = 0; i < 200; ++i) p.push_back({0.5 * i, 3.0, 2.0 + 0.01 * i});
  CHECK_THROWS(std::invalid_argument, lts_filter(p, LtsOptions{}));
}

// Scattered points written to four decimals all lie on multiples of 0.1 um: a grid of that step
// whose cells are nearly all empty, in which every window held only its own point and no outlier
// was ever found. They are scattered points, and their outliers are found.
TEST(LtsFilter, ScatteredPointsWrittenToFewDecimalsAreNotTakenForAGrid) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> x(0.0, 40.0), y(0.0, 30.0);
  std::normal_distribution<double> noise(0.0, 0.002);
  std::vector<Point3> p;
  std::set<size_t> spikes;
  for (size_t k = 0; k < 3000; ++k) {
    const double px = std::round(x(rng) * 1e4) / 1e4, py = std::round(y(rng) * 1e4) / 1e4;
    p.push_back({px, py, bowl(px, py) + noise(rng)});
    if (k % 100 == 7) {
      p.back().z += 0.3;
      spikes.insert(k);
    }
  }
  const LtsResult r = lts_filter(p, LtsOptions{});
  CHECK(!r.gridded);
  std::set<size_t> found;
  for (const auto& o : r.outliers) found.insert(o.index);
  for (size_t k : spikes) CHECK(found.count(k) == 1);
}

// A window of more than 64 points (9 x 9) holds its subsets as sorted lists instead of masks of
// places: it finds the spikes, and leaves the other points' heights, as a window of 7 x 7 does.
TEST(LtsFilter, AWindowOfMoreThanSixtyFourPointsFindsTheSameSpikes) {
  std::set<size_t> spikes;
  const std::vector<Point3> p = grid_with_spikes(spikes, true);
  for (int window : {7, 9}) {
    LtsOptions o;
    o.window = window;
    const LtsResult r = lts_filter(p, o);
    std::set<size_t> found;
    for (const auto& outlier : r.outliers) found.insert(outlier.index);
    for (size_t k : spikes) {
      CHECK_TEXT(found.count(k) == 1, ("window " + std::to_string(window) + " missed spike " + std::to_string(k)).c_str());
      DOUBLES_EQUAL(bowl(p[k].x, p[k].y), r.z[k], 0.01);
    }
    CHECK(found.size() <= spikes.size() + 12);
  }
}

TEST(LtsFilter, ALargeCloudInRandomOrderIsAnsweredInItsOwnOrder) {
  // 100,000 scattered points in random order are filtered in a spatial order inside; the outliers,
  // the heights and their numbers come back as the caller numbers the points.
  PointCloud c = dg::test::scattered_cloud(kSpatialOrderFrom, 100.0, 100.0, 9, 0.002, [](double x, double y) {
    return 3.0 + 0.002 * ((x - 50) * (x - 50) + (y - 50) * (y - 50)) + 0.3 * std::sin(x / 9.0) * std::sin(y / 11.0);
  });
  CHECK_FALSE(spatially_ordered(c.points));
  std::set<size_t> planted;
  for (size_t i = 500; i < c.points.size(); i += 997) {
    c.points[i].z += 0.1;  // 50 sigma
    planted.insert(i);
  }
  const LtsResult r = lts_filter(c.points, LtsOptions{});
  CHECK_FALSE(r.gridded);
  LONGS_EQUAL(c.points.size(), r.z.size());
  std::set<size_t> found;
  for (size_t k = 0; k < r.outliers.size(); ++k) {
    const LtsOutlier& o = r.outliers[k];
    if (k > 0) CHECK(r.outliers[k - 1].index < o.index);
    found.insert(o.index);
    DOUBLES_EQUAL(c.points[o.index].z - r.z[o.index], o.residual_mm, 1e-12);
  }
  CHECK(found == planted);
  for (size_t i = 0; i < c.points.size(); ++i) {
    if (!planted.count(i)) DOUBLES_EQUAL(c.points[i].z, r.z[i], 0);
  }
  // Each replaced by its own window's estimate: within a few noise sigmas of the part inside, 14 um
  // at worst where the window is one-sided at the edge. Another point's estimate is millimetres off.
  for (size_t i : planted) DOUBLES_EQUAL(0.1, c.points[i].z - r.z[i], 0.02);
}

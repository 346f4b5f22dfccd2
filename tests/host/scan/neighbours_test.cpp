// Nearest neighbours by rings of buckets, against a full search (indices, ties to the lower one),
// also for points on a line (whose bounding box has no area).
#include "host/scan/neighbours.h"

#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

using namespace dg::host;

namespace {

// Every `stride`-th point's k nearest exactly as a full search gives them: every (distance, index)
// sorted, so ties go to the lower index.
void check_against_brute_force(const std::vector<Point3>& p, size_t k, size_t stride = 7) {
  std::vector<std::vector<size_t>> hood;
  nearest_neighbourhoods(p, k, hood);
  LONGS_EQUAL(p.size(), hood.size());
  for (size_t i = 0; i < p.size(); i += stride) {
    std::vector<std::pair<double, size_t>> all;
    for (size_t j = 0; j < p.size(); ++j) {
      all.push_back({(p[j].x - p[i].x) * (p[j].x - p[i].x) + (p[j].y - p[i].y) * (p[j].y - p[i].y), j});
    }
    std::partial_sort(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(k), all.end());
    LONGS_EQUAL(k, hood[i].size());
    for (size_t m = 0; m < k; ++m) LONGS_EQUAL(all[m].second, hood[i][m]);
  }
}

}  // namespace

TEST_GROUP(Neighbours){};

TEST(Neighbours, TheFiveNearestAreExactWithTiesToTheLowerIndexOnScatteredPointsAndOnAGrid) {
  // Only the cells around a point that may hold a nearer point are searched; a grid's many equal
  // distances must still go to the lower index, as a full search gives them.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> x(0, 40), y(0, 30);
  std::vector<Point3> scattered;
  for (int i = 0; i < 2000; ++i) scattered.push_back({x(rng), y(rng), 0});
  check_against_brute_force(scattered, 5, 1);
  std::vector<Point3> grid;
  for (int row = 0; row < 31; ++row) {
    for (int column = 0; column < 41; ++column) grid.push_back({0.2 * column, 0.2 * row, 0});
  }
  check_against_brute_force(grid, 5, 1);
  check_against_brute_force(grid, 9, 1);
}

TEST(Neighbours, AFewNearestAreExactWhetherTheBlockAboutThePointHoldsThemOrNot) {
  // Up to eight neighbours come from the 3 x 3 cells about a point's own when they prove them; in
  // tight clusters among sparse points they often do not (the cells are sized by the mean density),
  // and the search goes on by rings. Coordinates on a coarse lattice make many equal distances.
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> x(0, 40), y(0, 30), spread(-0.3, 0.3);
  std::vector<Point3> p;
  for (int i = 0; i < 600; ++i) p.push_back({x(rng), y(rng), 0});
  for (int cluster = 0; cluster < 6; ++cluster) {
    const double cx = x(rng), cy = y(rng);
    for (int i = 0; i < 150; ++i) p.push_back({cx + spread(rng), cy + spread(rng), 0});
  }
  for (int i = 0; i < 300; ++i) p.push_back({std::round(x(rng)), std::round(y(rng)), 0});
  for (size_t k = 1; k <= 9; ++k) check_against_brute_force(p, k, 1);
}

TEST(Neighbours, ScatteredPointsGetTheirTrueNearest) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> x(0, 40), y(0, 30);
  std::vector<Point3> p;
  for (int i = 0; i < 1500; ++i) p.push_back({x(rng), y(rng), 0});
  check_against_brute_force(p, 25);
}

TEST(Neighbours, PointsOnOneLineGetTheirTrueNearestWithoutEndlessRings) {
  std::vector<Point3> p;
  for (int i = 0; i < 2000; ++i) p.push_back({0.5 * i, 3.0, 0});
  check_against_brute_force(p, 25);
}

TEST(Neighbours, TheFlatFormHoldsTheSameNeighboursAndAnOrderOfEveryPoint) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(0, 40), y(0, 30);
  std::vector<Point3> p;
  for (int i = 0; i < 3000; ++i) p.push_back({x(rng), y(rng), 0});
  std::vector<std::vector<size_t>> hood;
  nearest_neighbourhoods(p, 6, hood);
  const Neighbourhoods flat = nearest_neighbours(p, 6);
  LONGS_EQUAL(6, flat.k);
  for (size_t i = 0; i < p.size(); ++i) {
    for (size_t m = 0; m < 6; ++m) LONGS_EQUAL(hood[i][m], flat.of(i)[m]);
  }
  // The order visits every point once, and consecutive points in it lie close together.
  std::vector<size_t> sorted(flat.order.begin(), flat.order.end());
  std::sort(sorted.begin(), sorted.end());
  for (size_t i = 0; i < sorted.size(); ++i) LONGS_EQUAL(i, sorted[i]);
  double step_sum = 0;
  for (size_t n = 1; n < flat.order.size(); ++n) {
    const Point3 &a = p[flat.order[n - 1]], &b = p[flat.order[n]];
    step_sum += std::hypot(a.x - b.x, a.y - b.y);
  }
  CHECK(step_sum / static_cast<double>(p.size()) < 1.5);  // random order: about 17 mm a step
  const Neighbourhoods few = nearest_neighbours(std::vector<Point3>{{0, 0, 0}, {1, 0, 0}}, 5);
  LONGS_EQUAL(2, few.k);
  LONGS_EQUAL(1, few.of(0)[1]);
}

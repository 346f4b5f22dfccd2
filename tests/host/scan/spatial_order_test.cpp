// The spatial order of scattered points: every point once, neighbours near each other, columns kept.
#include "host/scan/spatial_order.h"

#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "tests/support/scattered_cloud.h"

using namespace dg::host;

namespace {

double mean_step_mm(const std::vector<Point3>& points) {
  double sum = 0;
  for (size_t k = 1; k < points.size(); ++k) {
    sum += std::hypot(points[k].x - points[k - 1].x, points[k].y - points[k - 1].y);
  }
  return sum / static_cast<double>(points.size() - 1);
}

PointCloud cloud_of(size_t count) {
  return dg::test::scattered_cloud(count, 40.0, 30.0, 7, 0.002, [](double x, double y) { return 2 + 0.01 * x * y; });
}

}  // namespace

TEST_GROUP(SpatialOrder) {};

TEST(SpatialOrder, TakesEveryPointOnce) {
  const PointCloud c = cloud_of(20000);
  std::vector<uint32_t> order = spatial_order(c.points);
  LONGS_EQUAL(c.points.size(), order.size());
  std::sort(order.begin(), order.end());
  for (size_t k = 0; k < order.size(); ++k) LONGS_EQUAL(k, order[k]);
}

TEST(SpatialOrder, PointsNextInTheOrderLieNextToEachOtherOnTheTable) {
  // 20,000 points over 40 x 30 mm: about 0.35 mm apart. In their random order consecutive points
  // are about 17 mm apart; in rows of cells of four points, about one cell.
  const PointCloud c = cloud_of(20000);
  const PointCloud ordered = reordered(c, spatial_order(c.points));
  CHECK(mean_step_mm(c.points) > 10.0);
  CHECK(mean_step_mm(ordered.points) < 1.0);
}

TEST(SpatialOrder, PointsAtOnePlaceKeepTheirOrderInTheFile) {
  std::vector<Point3> points = {{5, 5, 1}, {0, 0, 0}, {5, 5, 2}, {10, 10, 0}, {5, 5, 3}};
  const std::vector<uint32_t> order = spatial_order(points);
  std::vector<uint32_t> at_five;
  for (uint32_t i : order) {
    if (points[i].x == 5) at_five.push_back(i);
  }
  CHECK((at_five == std::vector<uint32_t>{0, 2, 4}));
}

TEST(SpatialOrder, EachPointTakesItsLineSigmaAndNormalAlong) {
  PointCloud c = cloud_of(500);
  c.line.emplace();
  c.sigma.emplace();
  c.normal.emplace();
  for (size_t i = 0; i < c.points.size(); ++i) {
    c.line->push_back(static_cast<uint32_t>(i));
    c.sigma->push_back(0.001 * static_cast<double>(i + 1));
    c.normal->push_back({0, 0, static_cast<double>(i)});
  }
  c.resolution_mm = 0.001;
  c.calibration = "table calibration";
  const std::vector<uint32_t> order = spatial_order(c.points);
  const std::vector<double> weights = reordered(*c.sigma, order);
  const PointCloud r = reordered(c, order);
  for (size_t k = 0; k < order.size(); ++k) {
    const size_t i = order[k];
    DOUBLES_EQUAL(c.points[i].x, r.points[k].x, 0);
    DOUBLES_EQUAL(c.points[i].z, r.points[k].z, 0);
    LONGS_EQUAL(i, (*r.line)[k]);
    DOUBLES_EQUAL((*c.sigma)[i], (*r.sigma)[k], 0);
    DOUBLES_EQUAL((*c.sigma)[i], weights[k], 0);
    DOUBLES_EQUAL(static_cast<double>(i), (*r.normal)[k].z, 0);
  }
  DOUBLES_EQUAL(0.001, *r.resolution_mm, 0);
  STRCMP_EQUAL("table calibration", r.calibration.c_str());
}

TEST(SpatialOrder, PointsOnOneLineOrAtOnePlaceAreOrdered) {
  // No area: the cells are a share of the line's length, not of no width.
  std::vector<Point3> line;
  for (int i = 0; i < 1000; ++i) line.push_back({static_cast<double>((i * 7919) % 1000), 3.0, 0});
  const std::vector<uint32_t> along = spatial_order(line);
  LONGS_EQUAL(1000, along.size());
  for (size_t k = 1; k < along.size(); ++k) CHECK(line[along[k]].x >= line[along[k - 1]].x - 4.0);
  const std::vector<uint32_t> one_place = spatial_order(std::vector<Point3>(3, Point3{1, 1, 1}));
  CHECK((one_place == std::vector<uint32_t>{0, 1, 2}));
  CHECK(spatial_order({}).empty());
}

TEST(SpatialOrder, TellsAScannersOrderAndItsOwnFromARandomOne) {
  // A 300 x 300 grid read row by row: one long step a row. Shuffled, nearly every step is long.
  std::vector<Point3> rows;
  for (int j = 0; j < 300; ++j) {
    for (int i = 0; i < 300; ++i) rows.push_back({0.1 * i, 0.1 * j, 1.0});
  }
  CHECK(spatially_ordered(rows));
  std::vector<Point3> shuffled = rows;
  std::mt19937 rng(3);
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  CHECK_FALSE(spatially_ordered(shuffled));
  const PointCloud c = cloud_of(20000);
  CHECK_FALSE(spatially_ordered(c.points));
  CHECK(spatially_ordered(reordered(c, spatial_order(c.points)).points));
}

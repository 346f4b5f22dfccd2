// Scan-line segmentation: Hamdan 2010, Table 1, atypical first steps, raster, serpentine,
// unequal lines.
#include "host/scan/segment.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <vector>

namespace {

using dg::host::Point3;

// Hamdan 2010, Table 1: 49 assumed CMM points on 7 curves of 7 points.
const double kTable1[49][3] = {
    {5.0000, 5.0000, 5.0000},    {7.2500, 5.6503, 7.0205},    {9.5000, 5.8820, 8.4740},
    {11.7500, 5.8167, 9.1985},   {14.0000, 5.5760, 9.0320},   {16.2500, 5.2813, 7.8125},
    {18.5000, 5.0540, 5.3780},   {6.6594, 7.5706, 6.1475},    {9.1631, 8.6528, 8.0374},
    {11.6299, 9.3622, 9.4464},   {14.1209, 9.6941, 10.2174},  {16.6971, 9.6437, 10.1930},
    {19.4199, 9.2063, 9.2161},   {22.3503, 8.3771, 7.1294},   {7.4750, 10.7150, 6.8900},
    {10.1409, 12.0841, 8.6838},  {12.8864, 13.0904, 10.0422}, {15.7744, 13.6657, 10.8304},
    {18.8674, 13.7417, 10.9136}, {22.2282, 13.2503, 10.1569}, {25.9196, 12.1232, 8.4254},
    {7.9531, 14.3319, 7.2275},   {10.6914, 15.8268, 8.9736},  {13.6927, 16.9797, 10.3067},
    {16.9896, 17.7021, 11.1169}, {20.6146, 17.9060, 11.2942}, {24.6004, 17.5030, 10.7287},
    {28.9793, 16.4049, 9.3102},  {8.6000, 18.3200, 7.1600},   {11.3228, 19.7638, 8.9207},
    {14.4718, 20.9432, 10.2854}, {18.0456, 21.7740, 11.1563}, {22.0427, 22.1723, 11.4356},
    {26.4616, 22.0539, 11.0255}, {31.3010, 21.3347, 9.8280},  {9.9219, 22.5781, 6.6875},
    {12.5433, 23.7778, 8.5389},  {15.6470, 24.8941, 10.0235}, {19.2215, 25.8519, 11.0279},
    {23.2554, 26.5764, 11.4384}, {27.7373, 26.9924, 11.1414}, {32.6559, 27.0251, 10.0233},
    {12.4250, 27.0050, 5.8100},  {14.8611, 27.7516, 7.8421},  {17.6414, 28.7455, 9.5666},
    {20.7963, 29.9064, 10.8110}, {24.3566, 31.1541, 11.4030}, {28.3527, 32.4082, 11.1702},
    {32.8155, 33.5887, 9.9402}};

double height(double x, double y) { return 5.0 + 0.3 * std::sin(x / 7.0) + 0.2 * std::cos(y / 5.0); }

// A grid scan of nx points per line (or per-line counts), in raster or serpentine order.
std::vector<Point3> grid(const std::vector<int>& counts, bool serpentine, double step, double cross) {
  std::vector<Point3> points;
  for (size_t line = 0; line < counts.size(); ++line) {
    const bool reverse = serpentine && (line & 1u);
    for (int k = 0; k < counts[line]; ++k) {
      const int i = reverse ? counts[line] - 1 - k : k;
      const double x = i * step, y = static_cast<double>(line) * cross;
      points.push_back({x, y, height(x, y)});
    }
  }
  return points;
}

std::vector<uint32_t> expected_lines(const std::vector<int>& counts) {
  std::vector<uint32_t> lines;
  for (size_t line = 0; line < counts.size(); ++line) {
    for (int k = 0; k < counts[line]; ++k) lines.push_back(static_cast<uint32_t>(line));
  }
  return lines;
}

}  // namespace

TEST_GROUP(SegmentLines){};

TEST(SegmentLines, SplitsSeed000Table1IntoItsSevenCurves) {
  std::vector<Point3> points;
  for (const auto& p : kTable1) points.push_back({p[0], p[1], p[2]});
  const std::vector<uint32_t> lines = dg::host::segment_lines(points);
  for (size_t i = 0; i < points.size(); ++i) LONGS_EQUAL(i / 7, lines[i]);
}

TEST(SegmentLines, SplitsRasterScans) {
  const std::vector<int> counts(6, 41);
  CHECK(dg::host::segment_lines(grid(counts, false, 1.0, 1.0)) == expected_lines(counts));
}

TEST(SegmentLines, SplitsSerpentineScansWhoseCrossFeedEqualsTheStep) {
  const std::vector<int> counts(6, 41);
  CHECK(dg::host::segment_lines(grid(counts, true, 1.0, 1.0)) == expected_lines(counts));
}

TEST(SegmentLines, SplitsSerpentineScansWithAShortCrossFeed) {
  const std::vector<int> counts(5, 30);
  CHECK(dg::host::segment_lines(grid(counts, true, 1.0, 0.5)) == expected_lines(counts));
}

TEST(SegmentLines, SplitsLinesOfUnequalLength) {
  const std::vector<int> counts = {12, 30, 5, 41, 2, 17};
  CHECK(dg::host::segment_lines(grid(counts, false, 1.0, 2.0)) == expected_lines(counts));
  CHECK(dg::host::segment_lines(grid(counts, true, 1.0, 2.0)) == expected_lines(counts));
}

TEST(SegmentLines, ToleratesAnAtypicalFirstStep) {
  // The probe's first move is short (backlash taken up); Hamdan's (2010) first-step
  // threshold would then split every ordinary step.
  const std::vector<int> counts(4, 20);
  std::vector<Point3> points = grid(counts, false, 1.0, 1.5);
  points[0].x = points[1].x - 0.2;
  CHECK(dg::host::segment_lines(points) == expected_lines(counts));
}

TEST(SegmentLines, KeepsASingleLineWhole) {
  const std::vector<int> counts = {50};
  CHECK(dg::host::segment_lines(grid(counts, false, 0.5, 1.0)) == expected_lines(counts));
  CHECK(dg::host::segment_lines({}).empty());
  LONGS_EQUAL(1, dg::host::segment_lines({{1, 2, 3}}).size());
}

// Counting sort of points into rows of cells, for the cache's sake (spatial_order.h).
#include "host/scan/spatial_order.h"

#include <algorithm>
#include <cmath>

namespace dg::host {

namespace {

struct Box {
  double x0, x1, y0, y1;
};

Box box_of(const std::vector<Point3>& points) {
  Box b{HUGE_VAL, -HUGE_VAL, HUGE_VAL, -HUGE_VAL};
  for (const Point3& p : points) {
    b.x0 = std::min(b.x0, p.x), b.x1 = std::max(b.x1, p.x), b.y0 = std::min(b.y0, p.y), b.y1 = std::max(b.y1, p.y);
  }
  return b;
}

}  // namespace

std::vector<uint32_t> spatial_order(const std::vector<Point3>& points) {
  const size_t count = points.size();
  if (count == 0 || count > UINT32_MAX) return {};
  const auto [x0, x1, y0, y1] = box_of(points);
  // About four points a cell, as the nearest-neighbour search's buckets; at least four points'
  // share of the longer side, so points on one line do not make a cell of no width.
  const double n = static_cast<double>(count);
  const double area = std::max((x1 - x0) * (y1 - y0), 1e-12);
  const double cell = std::max({std::sqrt(area * 4.0 / n), 4.0 * std::max(x1 - x0, y1 - y0) / n, 1e-9});
  const size_t columns = static_cast<size_t>(std::floor((x1 - x0) / cell)) + 1;
  const size_t rows = static_cast<size_t>(std::floor((y1 - y0) / cell)) + 1;
  std::vector<uint32_t> cell_of(count);
  std::vector<size_t> start(columns * rows + 1, 0);
  for (size_t i = 0; i < count; ++i) {
    const size_t cx = std::min(columns - 1, static_cast<size_t>((points[i].x - x0) / cell));
    const size_t cy = std::min(rows - 1, static_cast<size_t>((points[i].y - y0) / cell));
    cell_of[i] = static_cast<uint32_t>(cy * columns + cx);
    ++start[cell_of[i] + 1];
  }
  for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  std::vector<uint32_t> order(count);
  for (size_t i = 0; i < count; ++i) order[start[cell_of[i]]++] = static_cast<uint32_t>(i);
  return order;
}

bool spatially_ordered(const std::vector<Point3>& points) {
  if (points.size() < 2) return true;
  const auto [x0, x1, y0, y1] = box_of(points);
  const double n = static_cast<double>(points.size());
  const double area = std::max((x1 - x0) * (y1 - y0), 1e-12);
  const double spacing = std::max(std::sqrt(area / n), std::max(x1 - x0, y1 - y0) / n);
  const double long_sq = 64 * spacing * spacing;
  size_t long_steps = 0;
  for (size_t k = 1; k < points.size(); ++k) {
    const double dx = points[k].x - points[k - 1].x, dy = points[k].y - points[k - 1].y;
    long_steps += dx * dx + dy * dy > long_sq;
  }
  return static_cast<double>(long_steps) < 0.1 * (n - 1);
}

PointCloud reordered(PointCloud cloud, const std::vector<uint32_t>& order) {
  cloud.points = reordered(cloud.points, order);
  if (cloud.line) cloud.line = reordered(*cloud.line, order);
  if (cloud.normal) cloud.normal = reordered(*cloud.normal, order);
  if (cloud.sigma) cloud.sigma = reordered(*cloud.sigma, order);
  return cloud;
}

}  // namespace dg::host

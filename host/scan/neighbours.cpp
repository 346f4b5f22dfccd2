// k nearest points by rings of buckets: a ring more than the one that first holds k points within
// its reach, since a point in the next ring may still be nearer than some of them.
#include "host/scan/neighbours.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace dg::host {

void nearest_neighbourhoods(const std::vector<Point3>& points, size_t k, std::vector<std::vector<size_t>>& out) {
  double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
  for (const auto& p : points) x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  const double area = std::max((x1 - x0) * (y1 - y0), 1e-12);
  // About 4 points a cell; points on (nearly) one line have no area, so the cell is also at least
  // four points' share of the longer side (else it collapses and the rings grow for ever).
  const double n = static_cast<double>(points.size());
  const double cell = std::max({std::sqrt(area * 4.0 / n), 4.0 * std::max(x1 - x0, y1 - y0) / n, 1e-9});
  std::unordered_map<long long, std::vector<size_t>> buckets;
  // Unsigned arithmetic: cell coordinates may be negative one ring out from the edge.
  auto key = [](long cx, long cy) {
    return static_cast<long long>((static_cast<unsigned long long>(cx) << 32) ^ (static_cast<unsigned long long>(cy) & 0xffffffffULL));
  };
  for (size_t i = 0; i < points.size(); ++i) {
    buckets[key(std::lround(std::floor((points[i].x - x0) / cell)), std::lround(std::floor((points[i].y - y0) / cell)))].push_back(i);
  }
  k = std::min(k, points.size());
  out.assign(points.size(), {});
  std::vector<std::pair<double, size_t>> candidates;
  for (size_t i = 0; i < points.size(); ++i) {
    const long cx = std::lround(std::floor((points[i].x - x0) / cell)), cy = std::lround(std::floor((points[i].y - y0) / cell));
    // Grow the ring until it holds k candidates and one more ring (points in it may be nearer).
    for (long ring = 1;; ++ring) {
      candidates.clear();
      for (long dy = -ring; dy <= ring; ++dy)
        for (long dx = -ring; dx <= ring; ++dx) {
          const auto it = buckets.find(key(cx + dx, cy + dy));
          if (it == buckets.end()) continue;
          for (size_t j : it->second) {
            const double ddx = points[j].x - points[i].x, ddy = points[j].y - points[i].y;
            candidates.push_back({ddx * ddx + ddy * ddy, j});
          }
        }
      // Every point within `ring * cell` of i has been seen; enough of them means done.
      const double reach = static_cast<double>(ring) * cell;
      const size_t within = static_cast<size_t>(std::count_if(candidates.begin(), candidates.end(),
                                                              [&](const auto& c) { return c.first <= reach * reach; }));
      if (within >= k || candidates.size() == points.size()) break;
    }
    std::partial_sort(candidates.begin(), candidates.begin() + static_cast<std::ptrdiff_t>(k), candidates.end());
    for (size_t m = 0; m < k; ++m) out[i].push_back(candidates[m].second);
  }
}

}  // namespace dg::host

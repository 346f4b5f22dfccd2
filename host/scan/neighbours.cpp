// k nearest points by rings of buckets: a ring more than the one that first holds k points within
// its reach, since a point in the next ring may still be nearer than some of them. The buckets are
// a dense grid of about four points a cell, kept as one array of point numbers with each cell's
// start (no hashing on the way), and the points are shared among the cores.
#include "host/scan/neighbours.h"

#include <algorithm>
#include <cmath>

#include "host/parallel/parallel_for.h"

namespace dg::host {

void nearest_neighbourhoods(const std::vector<Point3>& points, size_t k, std::vector<std::vector<size_t>>& out) {
  out.assign(points.size(), {});
  if (points.empty()) return;
  double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
  for (const auto& p : points) x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  const double area = std::max((x1 - x0) * (y1 - y0), 1e-12);
  // About 4 points a cell; points on (nearly) one line have no area, so the cell is also at least
  // four points' share of the longer side (else it collapses and the rings grow for ever). Either
  // way the grid has at most about n / 4 + its width + its height cells.
  const double n = static_cast<double>(points.size());
  const double cell = std::max({std::sqrt(area * 4.0 / n), 4.0 * std::max(x1 - x0, y1 - y0) / n, 1e-9});
  const long columns = static_cast<long>(std::floor((x1 - x0) / cell)) + 1, rows = static_cast<long>(std::floor((y1 - y0) / cell)) + 1;
  auto column_of = [&](const Point3& p) { return std::min(columns - 1, static_cast<long>(std::floor((p.x - x0) / cell))); };
  auto row_of = [&](const Point3& p) { return std::min(rows - 1, static_cast<long>(std::floor((p.y - y0) / cell))); };
  // Counting sort of the points by cell: cell c holds members[start[c] .. start[c + 1]).
  std::vector<size_t> start(static_cast<size_t>(columns * rows) + 1, 0), members(points.size());
  for (const Point3& p : points) ++start[static_cast<size_t>(row_of(p) * columns + column_of(p)) + 1];
  for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  {
    std::vector<size_t> fill(start.begin(), start.end() - 1);
    for (size_t i = 0; i < points.size(); ++i) members[fill[static_cast<size_t>(row_of(points[i]) * columns + column_of(points[i]))]++] = i;
  }
  k = std::min(k, points.size());
  std::vector<std::vector<std::pair<double, size_t>>> candidates_of(worker_count());
  parallel_for(points.size(), [&](size_t begin, size_t end, unsigned worker) {
    std::vector<std::pair<double, size_t>>& candidates = candidates_of[worker];
    for (size_t i = begin; i < end; ++i) {
      const long cx = column_of(points[i]), cy = row_of(points[i]);
      // Grow the ring until it holds k candidates and one more ring (points in it may be nearer).
      for (long ring = 1;; ++ring) {
        candidates.clear();
        for (long y = std::max(0L, cy - ring); y <= std::min(rows - 1, cy + ring); ++y)
          for (long x = std::max(0L, cx - ring); x <= std::min(columns - 1, cx + ring); ++x) {
            const size_t c = static_cast<size_t>(y * columns + x);
            for (size_t m = start[c]; m < start[c + 1]; ++m) {
              const size_t j = members[m];
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
      // (distance, index) pairs: ties go to the lower index, whatever order the cells gave them in.
      std::partial_sort(candidates.begin(), candidates.begin() + static_cast<std::ptrdiff_t>(k), candidates.end());
      out[i].reserve(k);
      for (size_t m = 0; m < k; ++m) out[i].push_back(candidates[m].second);
    }
  }, 64);
}

}  // namespace dg::host

// k nearest points by rings of buckets: a ring more than the one that first holds k points within
// its reach, since a point in the next ring may still be nearer than some of them; for a few
// neighbours the 3 x 3 block about the point's bucket first, which nearly always holds them. The buckets are
// a dense grid of about four points a cell, kept as one array of point numbers with each cell's
// start (no hashing on the way), and the points are shared among the cores.
#include "host/scan/neighbours.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "host/parallel/parallel_for.h"

namespace dg::host {

namespace {

// Up to this many neighbours, a point's are first sought among the 3 x 3 cells about its own.
constexpr size_t kBlockMostK = 8;

// The K-th smallest of `n` distances (HUGE_VAL for fewer than K): each passes through a row of K
// minima, the smaller kept and the larger passed on, by min and max alone.
template <size_t K>
double kth_smallest(const double* distance, size_t n) {
  double smallest[K];
  for (double& d : smallest) d = HUGE_VAL;
  for (size_t m = 0; m < n; ++m) {
    double passed = distance[m];
    for (size_t s = 0; s < K; ++s) {
      const double kept = std::min(smallest[s], passed);
      passed = std::max(smallest[s], passed);
      smallest[s] = kept;
    }
  }
  return smallest[K - 1];
}

}  // namespace

Neighbourhoods nearest_neighbours(const std::vector<Point3>& points, size_t k) {
  return nearest_neighbours(points.size(), [](const void* from, size_t i, double& x, double& y) {
    const Point3& p = (*static_cast<const std::vector<Point3>*>(from))[i];
    x = p.x, y = p.y;
  }, &points, k);
}

Neighbourhoods nearest_neighbours(size_t count, PlanePoint at, const void* from, size_t k) {
  Neighbourhoods out;
  if (count == 0) return out;
  if (count > kMostNeighbourPoints) {
    throw std::length_error("the nearest-neighbour search takes at most 4,294,967,295 points, not " +
                            std::to_string(count));
  }
  double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
  for (size_t i = 0; i < count; ++i) {
    double x, y;
    at(from, i, x, y);
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  }
  const double area = std::max((x1 - x0) * (y1 - y0), 1e-12);
  // About 4 points a cell; points on (nearly) one line have no area, so the cell is also at least
  // four points' share of the longer side (else it collapses and the rings grow for ever). Either
  // way the grid has at most about n / 4 + its width + its height cells.
  const double n = static_cast<double>(count);
  const double cell = std::max({std::sqrt(area * 4.0 / n), 4.0 * std::max(x1 - x0, y1 - y0) / n, 1e-9});
  const long columns = static_cast<long>(std::floor((x1 - x0) / cell)) + 1, rows = static_cast<long>(std::floor((y1 - y0) / cell)) + 1;
  // Truncation is the floor here (no point lies below x0 or y0), without a call into libm.
  auto column_of = [&](double x) { return std::min(columns - 1, static_cast<long>((x - x0) / cell)); };
  auto row_of = [&](double y) { return std::min(rows - 1, static_cast<long>((y - y0) / cell)); };
  // Counting sort of the points by cell: cell c holds members[start[c] .. start[c + 1]). Each
  // point's cell is worked out again for the placing rather than kept from the count: fresh memory
  // is dear (memory_reuse.h), and a million points' cells took 8 MB at the search's peak.
  std::vector<size_t> start(static_cast<size_t>(columns * rows) + 1, 0);
  std::vector<uint32_t> members(count);
  auto cell_at = [&](size_t i) {
    double x, y;
    at(from, i, x, y);
    return static_cast<size_t>(row_of(y) * columns + column_of(x));
  };
  for (size_t i = 0; i < count; ++i) ++start[cell_at(i) + 1];
  for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  {
    std::vector<size_t> fill(start.begin(), start.end() - 1);
    for (size_t i = 0; i < count; ++i) members[fill[cell_at(i)]++] = static_cast<uint32_t>(i);
  }
  k = std::min(k, count);
  out.k = k;
  out.nearest.reset(new uint32_t[count * k]);
  out.position.resize(count);
  for (size_t m = 0; m < members.size(); ++m) out.position[members[m]] = static_cast<uint32_t>(m);
  if (k == 0) {
    out.order = std::move(members);
    return out;
  }
  // The points' XY in cell order: a cell's candidates are then read from one run of memory, not
  // from wherever the caller keeps them (for a million points that was most of the time).
  std::vector<double> cell_xy(2 * count);
  for (size_t m = 0; m < members.size(); ++m) at(from, members[m], cell_xy[2 * m], cell_xy[2 * m + 1]);
  // Each ring adds only its new cells; the k best (distance, index) pairs so far are kept sorted, so
  // ties go to the lower index whatever order the cells give them in. Point i is done once its k-th
  // best lies within `ring * cell`: every point that near has been seen. Points are taken in cell
  // order too, so neighbouring searches share what the cache holds.
  parallel_for(count, [&](size_t begin, size_t end, unsigned) {
    // The chunk's own list: per-worker lists side by side in one array shared their cache line,
    // and every insert by one core stalled the other.
    // Kept sorted by hand, the few larger ones shifted up: a handful of moves, no search and no
    // std::vector bookkeeping.
    std::vector<std::pair<double, size_t>> best(k);
    size_t held = 0;
    // A candidate at `distance` kept if it ranks among the k best so far.
    auto offer = [&](double distance, size_t index) {
      if (held == k && distance > best[k - 1].first) return;
      const std::pair<double, size_t> candidate{distance, index};
      if (held == k && !(candidate < best[k - 1])) return;
      size_t slot = held < k ? held++ : k - 1;
      for (; slot > 0 && candidate < best[slot - 1]; --slot) best[slot] = best[slot - 1];
      best[slot] = candidate;
    };
    // The point at `position` gets the k best, nearest first.
    auto write_best = [&](size_t position) {
      uint32_t* nearest = out.nearest.get() + position * k;
      for (size_t b = 0; b < held; ++b) *nearest++ = static_cast<uint32_t>(best[b].second);
    };
    // For up to kBlockMostK neighbours: the 3 x 3 block of cells about the point's cell, gathered
    // once for the points of that cell (they come one after another). Each point measures its
    // distance to all of the block in one pass the compiler vectorizes, and only a point whose k-th
    // best the block does not prove searches on by rings below. On a million random points
    // (spatially ordered, 2 cores) the search took 0.10 s instead of 0.13, the same neighbours.
    std::vector<double> block_x, block_y, block_distance;
    std::vector<uint32_t> block_index, block_within;
    long block_cell = -1;
    size_t block_seen = 0;
    for (size_t position = begin; position < end; ++position) {
      const double xi = cell_xy[2 * position], yi = cell_xy[2 * position + 1];
      const long cx = column_of(xi), cy = row_of(yi);
      if (k <= kBlockMostK && cy * columns + cx != block_cell) {
        block_cell = cy * columns + cx;
        block_x.clear(), block_y.clear(), block_index.clear();
        auto gather = [&](size_t first, size_t last) {
          for (size_t m = first; m < last; ++m) {
            block_x.push_back(cell_xy[2 * m]), block_y.push_back(cell_xy[2 * m + 1]);
            block_index.push_back(members[m]);
          }
        };
        // A row of the block is one run of `members`: the cells lie along rows.
        for (long y = std::max(0L, cy - 1); y <= std::min(rows - 1, cy + 1); ++y) {
          gather(start[static_cast<size_t>(y * columns + std::max(0L, cx - 1))],
                 start[static_cast<size_t>(y * columns + std::min(columns - 1, cx + 1)) + 1]);
        }
        block_seen = block_x.size();
        block_distance.resize(block_seen);
        block_within.resize(block_seen);
      }
      if (k <= kBlockMostK) {
        const size_t n_block = block_seen;
        double* distance = block_distance.data();
        const double* bx = block_x.data();
        const double* by = block_y.data();
        for (size_t m = 0; m < n_block; ++m) {
          const double ddx = bx[m] - xi, ddy = by[m] - yi;
          distance[m] = ddx * ddx + ddy * ddy;
        }
        // The k-th smallest distance, by a row of k minima the candidates pass through (no branch
        // whose outcome the data decide: inserting each nearer candidate into a sorted list as it
        // came mispredicted, and was most of the search), then the candidates within it.
        double kth = HUGE_VAL;
        switch (k) {
          case 1: kth = kth_smallest<1>(distance, n_block); break;
          case 2: kth = kth_smallest<2>(distance, n_block); break;
          case 3: kth = kth_smallest<3>(distance, n_block); break;
          case 4: kth = kth_smallest<4>(distance, n_block); break;
          case 5: kth = kth_smallest<5>(distance, n_block); break;
          case 6: kth = kth_smallest<6>(distance, n_block); break;
          case 7: kth = kth_smallest<7>(distance, n_block); break;
          default: kth = kth_smallest<8>(distance, n_block); break;
        }
        size_t within = 0;
        for (size_t m = 0; m < n_block; ++m) {
          block_within[within] = static_cast<uint32_t>(m);
          within += distance[m] <= kth;
        }
        held = 0;
        for (size_t w = 0; w < within; ++w) offer(distance[block_within[w]], block_index[block_within[w]]);
        const double fx = std::clamp((xi - x0) / cell - static_cast<double>(cx), 0.0, 1.0);
        const double fy = std::clamp((yi - y0) / cell - static_cast<double>(cy), 0.0, 1.0);
        const double beyond = (1 + std::min({fx, 1 - fx, fy, 1 - fy})) * cell;
        if ((held == k && best[k - 1].first <= beyond * beyond * (1 - 1e-9)) || block_seen == count) {
          write_best(position);
          continue;
        }
      }
      held = 0;
      size_t seen = 0;
      auto take_cell = [&](long x, long y) {
        const size_t c = static_cast<size_t>(y * columns + x);
        seen += start[c + 1] - start[c];
        for (size_t m = start[c]; m < start[c + 1]; ++m) {
          const double ddx = cell_xy[2 * m] - xi, ddy = cell_xy[2 * m + 1] - yi;
          offer(ddx * ddx + ddy * ddy, members[m]);
        }
      };
      take_cell(cx, cy);
      // The eight cells around next, each only if it may still hold a point nearer than the k-th
      // best: about half of them for k = 5 at four points a cell. A cell whose nearest corner or
      // side lies farther than the k-th best holds nothing it keeps (a point at exactly that
      // distance might tie with a lower index, so it is still taken), and the k-th best only
      // shrinks, so a cell passed over stays so. They are taken in an order fixed by the quarter
      // of its cell the point lies in, near sides first, which tightens the bound early without
      // sorting the eight (that sort's mispredicted branches were half of the search).
      // The point's place in its cell, 0..1 (clamped: the last column and row take what rounding
      // puts on their far side). The bounds below are shrunk by a part in 1e9 against rounding.
      const double fx = std::clamp((xi - x0) / cell - static_cast<double>(cx), 0.0, 1.0);
      const double fy = std::clamp((yi - y0) / cell - static_cast<double>(cy), 0.0, 1.0);
      constexpr double kMargin = 1 - 1e-9;
      const int nx = fx < 0.5 ? -1 : 1, ny = fy < 0.5 ? -1 : 1;  // the nearer side along x and y
      const int around[8][2] = {{nx, 0}, {0, ny}, {nx, ny}, {-nx, 0}, {0, -ny}, {-nx, ny}, {nx, -ny}, {-nx, -ny}};
      int passed_over[8], passed = 0;
      for (int a = 0; a < 8; ++a) {
        const int dx = around[a][0], dy = around[a][1];
        if (cx + dx < 0 || cx + dx >= columns || cy + dy < 0 || cy + dy >= rows) continue;
        const double gx = dx < 0 ? fx : dx > 0 ? 1 - fx : 0, gy = dy < 0 ? fy : dy > 0 ? 1 - fy : 0;
        if (held == k && (gx * gx + gy * gy) * cell * cell * kMargin > best[k - 1].first) {
          passed_over[passed++] = a;
        } else {
          take_cell(cx + dx, cy + dy);
        }
      }
      // The cells around passed over are farther than the k-th best; every cell beyond them lies
      // at least a cell and the point's distance to its own cell's nearest side away.
      const double beyond = (1 + std::min({fx, 1 - fx, fy, 1 - fy})) * cell;
      bool done = (held == k && best[k - 1].first <= beyond * beyond * kMargin) || seen == count;
      if (!done) {
        for (int p = 0; p < passed; ++p) take_cell(cx + around[passed_over[p]][0], cy + around[passed_over[p]][1]);
      }
      for (long ring = 2; !done; ++ring) {
        // The cells at Chebyshev distance `ring` from (cx, cy), inside the grid.
        for (long y = std::max(0L, cy - ring); y <= std::min(rows - 1, cy + ring); ++y) {
          if (y == cy - ring || y == cy + ring) {
            for (long x = std::max(0L, cx - ring); x <= std::min(columns - 1, cx + ring); ++x) take_cell(x, y);
          } else {
            if (cx - ring >= 0) take_cell(cx - ring, y);
            if (cx + ring < columns) take_cell(cx + ring, y);
          }
        }
        const double reach = static_cast<double>(ring) * cell;
        done = (held == k && best[k - 1].first <= reach * reach) || seen == count;
      }
      write_best(position);
    }
  }, 64);
  out.order = std::move(members);
  return out;
}

void nearest_neighbourhoods(const std::vector<Point3>& points, size_t k, std::vector<std::vector<size_t>>& out) {
  const Neighbourhoods flat = nearest_neighbours(points, k);
  out.assign(points.size(), {});
  // On every core: a small allocation a point (a quarter of the LTS filter's set-up on 1e5 points).
  parallel_for(points.size(), [&](size_t begin, size_t end, unsigned) {
    for (size_t i = begin; i < end; ++i) out[i].assign(flat.of(i), flat.of(i) + flat.k);
  }, 4096);
}

}  // namespace dg::host

// The LTS filter's grid: cells of a regular XY grid, windows and lines of neighbours.
#include "host/scan/lts_grid.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "host/parallel/parallel_for.h"
#include "host/scan/neighbours.h"

namespace dg::host::lts {

namespace {

// The grid step along one axis if every value is (close to) a multiple of a common step from the
// smallest one; 0 otherwise.
double grid_step(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end(), [](double a, double b) { return std::fabs(a - b) < 1e-6; }),
               values.end());
  if (values.size() < 2) return 0;
  double step = HUGE_VAL;
  for (size_t i = 1; i < values.size(); ++i) step = std::min(step, values[i] - values[i - 1]);
  for (double v : values) {
    const double k = (v - values[0]) / step;
    if (std::fabs(k - std::round(k)) > 1e-3) return 0;
  }
  return step;
}


// The points of a grid by their cell (ix, iy): a dense array over the cells' box when that is not
// much larger than the points (a scan), else a sorted list searched by halves. A std::map of the
// cells was a tenth of the whole filter's time on a 120,000-point scan.
class GridCells {
 public:
  static constexpr size_t kNone = SIZE_MAX;
  explicit GridCells(const std::vector<std::pair<long, long>>& at) {
    lo_x_ = hi_x_ = at.empty() ? 0 : at[0].first;
    lo_y_ = hi_y_ = at.empty() ? 0 : at[0].second;
    for (const auto& [ix, iy] : at) {
      lo_x_ = std::min(lo_x_, ix), hi_x_ = std::max(hi_x_, ix), lo_y_ = std::min(lo_y_, iy), hi_y_ = std::max(hi_y_, iy);
    }
    const double box = (static_cast<double>(hi_x_ - lo_x_) + 1) * (static_cast<double>(hi_y_ - lo_y_) + 1);
    dense_ = box <= 16.0 * static_cast<double>(at.size()) + 1024;
    if (dense_) {
      width_ = hi_x_ - lo_x_ + 1;
      index_.assign(static_cast<size_t>(box), kNone);
    }
    for (size_t i = 0; i < at.size(); ++i) {
      if (dense_) {
        size_t& slot = index_[offset(at[i].first, at[i].second)];
        if (slot != kNone) duplicate_ = true;
        slot = i;
      } else {
        sorted_.push_back({at[i], i});
      }
    }
    if (!dense_) {
      std::sort(sorted_.begin(), sorted_.end());
      for (size_t k = 1; k < sorted_.size(); ++k) duplicate_ = duplicate_ || sorted_[k].first == sorted_[k - 1].first;
    }
  }
  bool has_duplicate() const { return duplicate_; }
  bool dense() const { return dense_; }
  // The point in cell (ix, iy), or kNone.
  size_t find(long ix, long iy) const {
    if (ix < lo_x_ || ix > hi_x_ || iy < lo_y_ || iy > hi_y_) return kNone;
    if (dense_) return index_[offset(ix, iy)];
    const auto it = std::lower_bound(sorted_.begin(), sorted_.end(), std::make_pair(std::make_pair(ix, iy), size_t{0}));
    return it != sorted_.end() && it->first == std::make_pair(ix, iy) ? it->second : kNone;
  }
  long lo_x() const { return lo_x_; }
  long hi_x() const { return hi_x_; }
  long lo_y() const { return lo_y_; }
  long hi_y() const { return hi_y_; }

 private:
  size_t offset(long ix, long iy) const { return static_cast<size_t>((iy - lo_y_) * width_ + (ix - lo_x_)); }
  long lo_x_ = 0, hi_x_ = 0, lo_y_ = 0, hi_y_ = 0, width_ = 0;
  bool dense_ = false, duplicate_ = false;
  std::vector<size_t> index_;
  std::vector<std::pair<std::pair<long, long>, size_t>> sorted_;
};


}  // namespace

void WindowLists::reset(size_t n, size_t slots) {
  slots_ = slots;
  index_.reset(new uint32_t[n * slots]);
  count_.assign(n, 0);
}

void WindowLists::set(size_t i, const size_t* members, size_t count) {
  uint32_t* slot = index_.get() + i * slots_;
  for (size_t m = 0; m < count; ++m) slot[m] = static_cast<uint32_t>(members[m]);
  count_[i] = static_cast<uint32_t>(count);
}

void WindowLists::set(size_t i, const uint32_t* members, size_t count) {
  std::copy(members, members + count, index_.get() + i * slots_);
  count_[i] = static_cast<uint32_t>(count);
}

void nearest_windows(const std::vector<Point3>& points, size_t k, WindowLists& out) {
  const Neighbourhoods flat = nearest_neighbours(points, k);
  out.reset(points.size(), flat.k);
  parallel_for(points.size(), [&](size_t begin, size_t end, unsigned) {
    for (size_t i = begin; i < end; ++i) out.set(i, flat.of(i), flat.k);
  }, 4096);
}

bool grid_neighbourhoods(const std::vector<Point3>& points, int window, WindowLists& out,
                         std::vector<std::vector<size_t>>& rows_and_columns, std::vector<LineSides>& sides,
                         WindowLists* wide) {
  std::vector<double> xs, ys;
  for (const auto& p : points) xs.push_back(p.x), ys.push_back(p.y);
  const double sx = grid_step(xs), sy = grid_step(ys);
  if (!(sx > 0) || !(sy > 0)) return false;
  const double x0 = *std::min_element(xs.begin(), xs.end()), y0 = *std::min_element(ys.begin(), ys.end());
  std::vector<std::pair<long, long>> at(points.size());
  long cells_x = 0, cells_y = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    at[i] = {std::lround((points[i].x - x0) / sx), std::lround((points[i].y - y0) / sy)};
    cells_x = std::max(cells_x, at[i].first + 1), cells_y = std::max(cells_y, at[i].second + 1);
  }
  // A scan's grid holds a point in most of its cells. Scattered points written to a few decimals
  // are all multiples of the last decimal too: a "grid" of 0.1 um whose cells are nearly all empty,
  // each window holding its own point alone, so that no outlier could ever be told (a 20,000-point
  // cloud at 4 decimals kept 400 outliers of 150 sigma and reported none). Fewer points than a
  // quarter of the cells: the nearest neighbours instead.
  if (static_cast<double>(points.size()) < 0.25 * static_cast<double>(cells_x) * static_cast<double>(cells_y)) return false;
  const GridCells cell(at);
  if (cell.has_duplicate()) return false;  // two points in one grid cell: not a grid
  const long lo_x = cell.lo_x(), hi_x = cell.hi_x(), lo_y = cell.lo_y(), hi_y = cell.hi_y();
  // The grid's rows and columns in order, for the noise estimate (gaps break the even spacing
  // the estimate asks of each window, so they need no care here). The occupied rows (by y) and
  // columns (by x), each in order along it.
  std::vector<std::vector<size_t>> rows(static_cast<size_t>(hi_y - lo_y + 1)), columns(static_cast<size_t>(hi_x - lo_x + 1));
  if (cell.dense()) {
    // Along the cells in order, one point a cell: no sort of the points (two sorts of 1e5 points
    // by their cells were 15 ms).
    for (long y = lo_y; y <= hi_y; ++y) {
      for (long x = lo_x; x <= hi_x; ++x) {
        const size_t j = cell.find(x, y);
        if (j == GridCells::kNone) continue;
        rows[static_cast<size_t>(y - lo_y)].push_back(j);
        columns[static_cast<size_t>(x - lo_x)].push_back(j);
      }
    }
  } else {
    std::vector<size_t> by_cell(points.size());
    for (size_t i = 0; i < points.size(); ++i) by_cell[i] = i;
    std::sort(by_cell.begin(), by_cell.end(), [&](size_t a, size_t b) { return at[a] < at[b]; });  // x, then y
    for (size_t i : by_cell) columns[static_cast<size_t>(at[i].first - lo_x)].push_back(i);
    std::sort(by_cell.begin(), by_cell.end(), [&](size_t a, size_t b) {
      return std::make_pair(at[a].second, at[a].first) < std::make_pair(at[b].second, at[b].first);
    });
    for (size_t i : by_cell) rows[static_cast<size_t>(at[i].second - lo_y)].push_back(i);
  }
  rows_and_columns.clear();
  for (auto* lines : {&rows, &columns}) {
    for (auto& sequence : *lines) {
      if (!sequence.empty()) rows_and_columns.push_back(std::move(sequence));
    }
  }
  // Near an edge of the scan the window shifts inward rather than being cut, so that a point at an
  // edge or a corner keeps a full window x window neighbourhood: a cut 3 x 3 corner window leaves a
  // plane on 8 points, whose curvature bias on a 1 mm grid is tens of sigma.
  // The window of `side` points round point i into `lists`, through the caller's `scratch`.
  auto window_of = [&](size_t i, long side, WindowLists& lists, std::vector<size_t>& scratch) {
    const long r = side / 2;
    auto start = [r](long index, long lo, long hi) { return hi - lo < 2 * r ? lo : std::clamp(index - r, lo, hi - 2 * r); };
    const long first_x = start(at[i].first, lo_x, hi_x), first_y = start(at[i].second, lo_y, hi_y);
    scratch.clear();
    for (long y = first_y; y <= first_y + 2 * r; ++y)
      for (long x = first_x; x <= first_x + 2 * r; ++x) {
        const size_t j = cell.find(x, y);
        if (j != GridCells::kNone) scratch.push_back(j);
      }
    lists.set(i, scratch.data(), scratch.size());
  };
  const auto slots = [](long side) { return static_cast<size_t>(side * side); };
  out.reset(points.size(), slots(window));
  sides.assign(points.size(), {});
  if (wide != nullptr) wide->reset(points.size(), slots(window + 2));
  static const long kStep[kLines][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}, {-1, -1}, {1, 1}, {-1, 1}, {1, -1}};
  // Each point's lists are its own, so the points are shared among the cores.
  parallel_for(points.size(), [&](size_t begin, size_t end, unsigned) {
    std::vector<size_t> scratch;
    for (size_t i = begin; i < end; ++i) {
      for (int d = 0; d < kLines; ++d) {
        for (long t = 1; t <= kLineReach; ++t) {
          const size_t j = cell.find(at[i].first + t * kStep[d][0], at[i].second + t * kStep[d][1]);
          if (j == GridCells::kNone) break;
          sides[i][d].push_back(j);
        }
      }
      window_of(i, window, out, scratch);
      if (wide != nullptr) window_of(i, window + 2, *wide, scratch);
    }
  });
  return true;
}

}  // namespace dg::host::lts

// The LTS filter's grid: each point's window of grid neighbours and its lines of neighbours along
// the rows, columns and diagonals.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "host/geometry/point3.h"

namespace dg::host::lts {

// Along a row, a column or a diagonal, a point on a sliver of surface between a crease and the
// scan's edge (too thin for any half-plane to hold mostly its own surface) still has neighbours on
// its own surface: one quadratic per side (kLines of them) may vouch for it but never replace it.
// Each side holds up to kLineReach grid neighbours, nearest first, contiguous (a gap ends the
// side); a line model uses the first kLinePoints of them that are not suspected outliers.
constexpr int kLines = 8;
constexpr long kLineReach = 8;

// One side of a point's line, held in place: with eight vectors of their own for every point the
// filter's peak on a 1e5-point grid with outliers was 306 MB, with these 253 MB (and 2.43 against
// 2.13 s, five runs each).
class LineSide {
 public:
  void push_back(size_t j) { index_[count_++] = static_cast<uint32_t>(j); }
  size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  size_t operator[](size_t k) const { return index_[k]; }
  size_t front() const { return index_[0]; }
  const uint32_t* begin() const { return index_; }
  const uint32_t* end() const { return index_ + count_; }

 private:
  uint32_t index_[kLineReach];
  uint8_t count_ = 0;
};
using LineSides = std::array<LineSide, kLines>;

// Point numbers in place, read as a window's or a line's members.
class IndexSpan {
 public:
  IndexSpan(const uint32_t* first, size_t count) : first_(first), count_(count) {}
  size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  size_t operator[](size_t k) const { return first_[k]; }
  const uint32_t* begin() const { return first_; }
  const uint32_t* end() const { return first_ + count_; }

 private:
  const uint32_t* first_;
  size_t count_;
};

// Every point's window of neighbours in one array, a fixed number of slots a point: a vector a
// point for the window and one for the wider window were 200,000 allocations on a 1e5-point grid,
// and the filter's peak there 227 MB against 192 MB with these.
class WindowLists {
 public:
  // n points, up to `slots` members each, none yet.
  void reset(size_t n, size_t slots);
  // Point i's members, set once (from one thread a point).
  void set(size_t i, const size_t* members, size_t count);
  void set(size_t i, const uint32_t* members, size_t count);
  IndexSpan operator[](size_t i) const { return {index_.get() + i * slots_, count_[i]}; }

 private:
  size_t slots_ = 0;
  // Not a std::vector: every slot in use is written, and zeroing them first would touch every page
  // on one core.
  std::unique_ptr<uint32_t[]> index_;
  std::vector<uint32_t> count_;
};

// When the points lie on a regular XY grid (holes allowed): true, with each point's window x window
// grid neighbourhood in `out` (shifted inwards at the scan's edges), the rows and columns in
// `rows_and_columns`, and each point's kLines sides of line neighbours in `sides`; with `wide`, also
// each point's (window + 2) x (window + 2) neighbourhood there. False otherwise.
bool grid_neighbourhoods(const std::vector<Point3>& points, int window, WindowLists& out,
                         std::vector<std::vector<size_t>>& rows_and_columns, std::vector<LineSides>& sides,
                         WindowLists* wide = nullptr);

// Every point's `k` nearest in XY (nearest_neighbours) as window lists: the windows of scattered
// points.
void nearest_windows(const std::vector<Point3>& points, size_t k, WindowLists& out);

}  // namespace dg::host::lts

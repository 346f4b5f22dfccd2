// The k nearest points in XY of every point of a cloud: the neighbourhoods of local fits.
#pragma once
#include <cstddef>
#include <memory>
#include <vector>

#include "host/geometry/point3.h"

namespace dg::host {

// Every point's k nearest in XY, in one array, kept in the buckets' order (the order the search
// writes them in: written by point number instead, each point's list landed in another cache line,
// and for a million points in random order those scattered stores took a quarter of the search).
struct Neighbourhoods {
  size_t k = 0;  // per point: the k asked for, capped at the number of points
  // Every point once, bucket by bucket along rows of buckets: points near in this order are near in
  // XY, so work taken in it finds each point's neighbours in what the cache already holds.
  std::vector<size_t> order;
  std::vector<size_t> position;  // point i is order[position[i]]
  // The k nearest of the point at order[p], nearest first, the point among them.
  const size_t* at_position(size_t p) const { return nearest.get() + p * k; }
  // Point i's k nearest, nearest first, i among them.
  const size_t* of(size_t i) const { return at_position(position[i]); }
  // The same as a range, for loops and indexing.
  struct List {
    const size_t* first;
    size_t count;
    const size_t* begin() const { return first; }
    const size_t* end() const { return first + count; }
    size_t size() const { return count; }
    size_t operator[](size_t m) const { return first[m]; }
  };
  List list(size_t i) const { return {of(i), k}; }
  List list_at_position(size_t p) const { return {at_position(p), k}; }
  // at_position(p)'s lists one after another. Not a std::vector: the search writes every entry, and
  // zeroing them first (40 MB for a million points at k = 5) was a tenth of the search, on one core.
  std::unique_ptr<size_t[]> nearest;
};

// Found through a bucket grid (ties go to the lower index).
Neighbourhoods nearest_neighbours(const std::vector<Point3>& points, size_t k);

// The same as one vector a point: out[i] holds the k nearest points to point i, nearest first.
void nearest_neighbourhoods(const std::vector<Point3>& points, size_t k, std::vector<std::vector<size_t>>& out);

}  // namespace dg::host

// The k nearest points in XY of every point of a cloud: the neighbourhoods of local fits.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "host/geometry/point3.h"

namespace dg::host {

// Every point's k nearest in XY, in one array, kept in the buckets' order (the order the search
// writes them in: written by point number instead, each point's list landed in another cache line,
// and for a million points in random order those scattered stores took a quarter of the search).
// Point numbers are 32-bit: fresh memory is dear (memory_reuse.h), and with 64-bit ones the lists
// of a million points at k = 5 took 40 MB instead of 20.
struct Neighbourhoods {
  size_t k = 0;  // per point: the k asked for, capped at the number of points
  // Every point once, bucket by bucket along rows of buckets: points near in this order are near in
  // XY, so work taken in it finds each point's neighbours in what the cache already holds.
  std::vector<uint32_t> order;
  std::vector<uint32_t> position;  // point i is order[position[i]]
  // The k nearest of the point at order[p], nearest first, the point among them.
  const uint32_t* at_position(size_t p) const { return nearest.get() + p * k; }
  // Point i's k nearest, nearest first, i among them.
  const uint32_t* of(size_t i) const { return at_position(position[i]); }
  // The same as a range, for loops and indexing.
  struct List {
    const uint32_t* first;
    size_t count;
    const uint32_t* begin() const { return first; }
    const uint32_t* end() const { return first + count; }
    size_t size() const { return count; }
    size_t operator[](size_t m) const { return first[m]; }
  };
  List list(size_t i) const { return {of(i), k}; }
  List list_at_position(size_t p) const { return {at_position(p), k}; }
  // at_position(p)'s lists one after another. Not a std::vector: the search writes every entry, and
  // zeroing them first was a tenth of the search, on one core.
  std::unique_ptr<uint32_t[]> nearest;
};

// The largest number of points a search takes (their numbers are 32-bit).
constexpr size_t kMostNeighbourPoints = UINT32_MAX;

// Point i's x and y, from the caller's `points`: the search reads the points through this once
// to sort them into its buckets, so the points need not be Point3s (the parameter plane's are not).
using PlanePoint = void (*)(const void* points, size_t i, double& x, double& y);

// Found through a bucket grid (ties go to the lower index). Throws std::length_error beyond
// kMostNeighbourPoints points.
Neighbourhoods nearest_neighbours(const std::vector<Point3>& points, size_t k);

// The same for `n` points that `at` reads from `points`.
Neighbourhoods nearest_neighbours(size_t n, PlanePoint at, const void* points, size_t k);

// The same as one vector a point: out[i] holds the k nearest points to point i, nearest first.
void nearest_neighbourhoods(const std::vector<Point3>& points, size_t k, std::vector<std::vector<size_t>>& out);

}  // namespace dg::host

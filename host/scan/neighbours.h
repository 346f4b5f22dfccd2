// The k nearest points in XY of every point of a cloud: the neighbourhoods of local fits.
#pragma once
#include <cstddef>
#include <vector>

#include "host/geometry/point3.h"

namespace dg::host {

// Every point's k nearest in XY, in one array.
struct Neighbourhoods {
  size_t k = 0;                 // per point: the k asked for, capped at the number of points
  std::vector<size_t> nearest;  // point i's k nearest at [i * k, (i + 1) * k), nearest first, i among them
  // Every point once, bucket by bucket along rows of buckets: points near in this order are near in
  // XY, so work taken in it finds each point's neighbours in what the cache already holds.
  std::vector<size_t> order;
  const size_t* of(size_t i) const { return nearest.data() + i * k; }
};

// Found through a bucket grid (ties go to the lower index).
Neighbourhoods nearest_neighbours(const std::vector<Point3>& points, size_t k);

// The same as one vector a point: out[i] holds the k nearest points to point i, nearest first.
void nearest_neighbourhoods(const std::vector<Point3>& points, size_t k, std::vector<std::vector<size_t>>& out);

}  // namespace dg::host

// The k nearest points in XY of every point of a cloud: the neighbourhoods of local fits.
#pragma once
#include <cstddef>
#include <vector>

#include "host/geometry/point3.h"

namespace dg::host {

// out[i] holds the k nearest points to point i in XY, nearest first (i itself among them), found
// through a bucket grid; k is capped at the number of points.
void nearest_neighbourhoods(const std::vector<Point3>& points, size_t k, std::vector<std::vector<size_t>>& out);

}  // namespace dg::host

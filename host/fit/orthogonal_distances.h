// Signed orthogonal distances of fitted points, each projection started from the point's own parameters.
#pragma once
#include <vector>

#include "host/fit/parameterize.h"
#include "host/geometry/bspline_surface.h"

namespace dg::host {

std::vector<double> orthogonal_distances(const BSplineSurface& surface, const std::vector<Point3>& points,
                                         const Parameters& params);

}  // namespace dg::host

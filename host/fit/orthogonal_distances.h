// Signed orthogonal distances of fitted points, each projection started from the point's own parameters.
#pragma once
#include <vector>

#include "host/fit/parameterize.h"
#include "host/geometry/bspline_surface.h"

namespace dg::host {

std::vector<double> orthogonal_distances(const BSplineSurface& surface, const std::vector<Point3>& points,
                                         const Parameters& params);

// The same, and each point's distance at its own parameters clamped to the surface's domain (an
// upper bound of the orthogonal one; parameter_distances' figure where they lie inside it) in
// `start`, from the same evaluation.
std::vector<double> orthogonal_distances(const BSplineSurface& surface, const std::vector<Point3>& points,
                                         const Parameters& params, std::vector<double>& start);

}  // namespace dg::host

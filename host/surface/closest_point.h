// Orthogonal (closest-point) distance from measured points to a B-spline surface.
#pragma once
#include <vector>

#include "host/surface/bspline_surface.h"
#include "host/surface/parameterize.h"

namespace dg::host {

struct Closest {
  double u = 0, v = 0;
  Point3 point;
  double distance = 0;  // signed: positive on the side of S_u x S_v (above a height field)
};

// Gauss-Newton on |P - S(u, v)|^2 from (u0, v0), clamped to the domain; at a boundary the
// iteration continues along the edge. Converges in a few steps from a point's own parameters.
Closest closest_point(const BSplineSurface& surface, const Point3& p, double u0, double v0);

// Signed orthogonal distances of all points, each started from its own parameters.
std::vector<double> orthogonal_distances(const BSplineSurface& surface, const std::vector<Point3>& points,
                                         const Parameters& params);

}  // namespace dg::host

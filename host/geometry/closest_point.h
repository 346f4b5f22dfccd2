// Orthogonal (closest-point) distance from measured points to a B-spline surface.
#pragma once
#include <vector>

#include "host/geometry/bspline_surface.h"

namespace dg::host {

struct Closest {
  double u = 0, v = 0;
  Point3 point;
  double distance = 0;  // signed: positive on the side of S_u x S_v (above a height field)
  Point3 normal;        // unit, towards positive distances, at the foot (0 where it has none)
  // |P - S(u0, v0)| with (u0, v0) clamped to the domain: the distance at the parameters it
  // started from, an upper bound of `distance`'s size.
  double start_distance = 0;
  // The foot lies on the surface's border, where the distance may run to the side of the surface
  // instead of along its normal: on a B-spline's domain edge (closest_point), or on an open mesh's
  // border (MeshLocator: an edge of one triangle, or a vertex on one).
  bool on_border = false;
};

// Gauss-Newton on |P - S(u, v)|^2 from (u0, v0), clamped to the domain; at a boundary the
// iteration continues along the edge. Converges in a few steps from a point's own parameters.
Closest closest_point(const BSplineSurface& surface, const Point3& p, double u0, double v0);

}  // namespace dg::host

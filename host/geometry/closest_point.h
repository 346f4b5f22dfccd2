// Orthogonal (closest-point) distance from measured points to a B-spline surface.
#pragma once
#include <vector>

#include "host/geometry/bspline_surface.h"
#include "host/geometry/patch_form.h"

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

// A point whose closest point lies on the surface's border counts as beyond its edge where the
// line to it leaves the normal there by more than this: 45 degrees, its distance more across than
// along the normal. A scan's own edge points on a slope are off the normal by the noise's share of
// the slope only (and by at most the slope's angle), so a fit's own scan has none beyond its edge
// unless it is steeper than 45 degrees there.
constexpr double kBeyondEdgeAngleDeg = 45;
// ... and only by more than this across the normal: a micrometre, below which the edge's own place
// is not known better (a fit's edge points, noise-free, sit off its edge by the rounding).
constexpr double kBeyondEdgeMinMm = 0.001;

// Whether `p`, whose closest point is `c`, lies beyond the surface's edge: `c` on the border and
// `p` off to the side of it (kBeyondEdgeAngleDeg, kBeyondEdgeMinMm). Its distance is then to the
// edge, not along a normal: it says nothing of the part's form there.
bool beyond_edge(const Point3& p, const Closest& c);

// Gauss-Newton on |P - S(u, v)|^2 from (u0, v0), clamped to the domain; at a boundary the
// iteration continues along the edge. Converges in a few steps from a point's own parameters.
Closest closest_point(const BSplineSurface& surface, const Point3& p, double u0, double v0);
// The same on the surface's power form, for many points on one surface (patch_form.h).
Closest closest_point(const PatchForm& surface, const Point3& p, double u0, double v0);

}  // namespace dg::host

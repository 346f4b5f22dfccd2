// A trimmed face: a height-field surface cut to the part of the table it describes by closed loops in XY.
#pragma once
#include <vector>

#include "host/geometry/bspline_surface.h"
#include "host/geometry/distance_stats.h"
#include "host/geometry/surface_uncertainty.h"

namespace dg::host {

struct Point2 {
  double x = 0, y = 0;  // mm, table coordinates
};

// A closed polygon, last vertex not repeated.
using TrimLoop = std::vector<Point2>;

struct TrimmedFace {
  BSplineSurface surface;      // a height field over a box that holds every loop
  std::vector<TrimLoop> loops;  // loops[0] the outer boundary (counter-clockwise), then holes (clockwise)
  // The fit of this face's region, when it was fitted here.
  size_t points = 0;        // the region's points
  DistanceStats distance;   // their orthogonal distances to this face, mm
  int iterations = 0;
  // The standard uncertainty of the face's height (k = 1) from the points' noise, on a 41 x 41
  // grid over its surface's domain, nodes outside the face kOffFace (host/fit/bspline_fit.h,
  // region_fit_uncertainty).
  SurfaceUncertainty uncertainty;
};

// Twice the signed area of a loop (positive counter-clockwise), mm^2.
double twice_signed_area(const TrimLoop& loop);
// Whether (x, y) lies inside the polygon (even-odd rule; a point on an edge counts either way).
bool inside_loop(const TrimLoop& loop, double x, double y);
// Inside the outer loop and outside every hole.
bool inside_face(const TrimmedFace& face, double x, double y);
// The parameters (u, v) of a height-field surface above table point (x, y): the surface's x and y
// are affine in (u, v) (control points at the Greville abscissae), read from its corner points.
void table_to_parameters(const BSplineSurface& surface, double x, double y, double& u, double& v);

// The surface point above table point (x, y).
Point3 point_above(const BSplineSurface& surface, double x, double y);

// The uncertainty grid `u` of the height field `surface` (over its parameter domain) at the point
// above table (x, y); false where the grid has no value (off a trimmed face's nodes, or no grid).
bool uncertainty_above(const BSplineSurface& surface, const SurfaceUncertainty& u, double x, double y, double& value);
// The loop with every edge cut into pieces no longer than `max_step_mm`, so a polyline through the
// surface points above its vertices stays on the surface (a straight edge in XY is a curve on it).
TrimLoop densified(const TrimLoop& loop, double max_step_mm);

}  // namespace dg::host

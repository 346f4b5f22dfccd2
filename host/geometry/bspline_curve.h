// A non-rational B-spline curve in millimetres: what CAD files carry as curves (edges, sections).
#pragma once
#include <vector>

#include "host/geometry/point3.h"
#include "host/geometry/bspline_surface.h"

namespace dg::host {

struct BSplineCurve {
  int degree = 3;
  std::vector<double> knots;    // control.size() + degree + 1, non-decreasing
  std::vector<Point3> control;  // mm
  double t_min() const { return knots[static_cast<size_t>(degree)]; }
  double t_max() const { return knots[control.size()]; }
  Point3 evaluate(double t) const;
};

// The four edges of a clamped surface: v = v_min, u = u_max, v = v_max, u = u_min (each running in
// increasing parameter). Clamp the surface first (clamp_ends) if it is not clamped.
std::vector<BSplineCurve> boundary_curves(const BSplineSurface& clamped);

}  // namespace dg::host

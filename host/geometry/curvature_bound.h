// Bounds on a B-spline surface's second derivatives over parameter boxes, from its control net.
#pragma once
#include <vector>

#include "host/geometry/bspline_surface.h"

namespace dg::host {

// A B-spline's derivative is a B-spline whose control points are scaled differences of the
// original ones (Piegl and Tiller 1997, sections 3.3 and 3.5), and a B-spline lies in the
// convex hull of the control points that reach a knot cell. So the largest second-difference
// control point over a cell bounds |S_uu|, |S_vv| and |S_uv| there, each coordinate, without
// evaluating anything. Along a unit direction e in (u, v), |e^T H e| <= max(|S_uu|, |S_vv|) + |S_uv|.
//
// What this buys: a function with |g''| <= M on [0, h] stays within M h^2 / 8 of its chord, and at
// the mean of some parameters within M/2 times their mean squared distance to it of the mean of its
// values there. Both need the first derivative continuous along the way, so a box that crosses a
// knot of multiplicity >= the degree (a crease: C0 or less) has no bound.
class CurvatureBound {
 public:
  explicit CurvatureBound(const BSplineSurface& surface);

  // The largest |d^2 S / dt^2| of any coordinate, mm per squared parameter unit, along any unit
  // direction within [u0, u1] x [v0, v1] (clamped to the domain); +infinity where the box crosses
  // a knot line across which the surface is not C1.
  double along_any_direction(double u0, double u1, double v0, double v1) const;
  // The same over the knot spans su0..su1 by sv0..sv1 (either order), for callers that find each
  // parameter's span once and reuse it.
  int span_u(double u) const;
  int span_v(double v) const;
  double over_spans(int su0, int su1, int sv0, int sv1) const;

 private:
  const BSplineSurface& surface_;
  int cells_u_ = 0, cells_v_ = 0;       // knot spans degree..count-1 in each direction
  std::vector<double> cell_bound_;       // max(|S_uu|, |S_vv|) + |S_uv| per span pair, by span index
  std::vector<char> kink_before_u_, kink_before_v_;  // span s starts at an interior knot of multiplicity >= degree
};

}  // namespace dg::host

// Clamping a B-spline surface: end knots of multiplicity degree + 1, so that its edges are the
// first and last rows of control points (what STEP's topology and most CAD programs expect).
#pragma once
#include "host/geometry/bspline_surface.h"

namespace dg::host {

// The same surface on [u_min, u_max] x [v_min, v_max] with clamped knot vectors, by knot insertion
// (Boehm) at the domain ends; exact up to rounding. A clamped surface comes back unchanged.
BSplineSurface clamp_ends(const BSplineSurface& surface);

}  // namespace dg::host

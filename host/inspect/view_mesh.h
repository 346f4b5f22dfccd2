// The surface the report's 3D view draws under the measured points: the part of a nominal's or a
// fitted surface's mesh around the points, coarsened to a size a page carries.
#pragma once
#include <cstddef>

#include "host/geometry/fitted_surface.h"
#include "host/geometry/tessellate.h"
#include "host/inspect/inspect.h"

namespace dg::host {

// The triangles with a corner inside the points' XY box widened by a tenth of its size on each
// side; if more than `max_triangles` remain, vertices are merged on a grid (each cell's mean),
// coarser until they fit, and triangles that collapse are dropped. Empty without points or
// triangles near them.
Mesh mesh_for_view(const Mesh& mesh, const Inspection& inspection, size_t max_triangles = 40000);

// A fitted surface (one B-spline, or trimmed faces) meshed to a thousandth of the points' extent,
// then as mesh_for_view; empty where it cannot be meshed within 400,000 triangles.
Mesh fitted_surface_for_view(const FittedSurface& surface, const Inspection& inspection);

}  // namespace dg::host

// Inspection: the signed orthogonal deviation of every measured point from a surface, its
// statistics, and the share of points within tolerance bands (Li and Zhang 2013, eq. 8 counts them).
#pragma once
#include <functional>
#include <vector>

#include "host/geometry/bspline_surface.h"
#include "host/geometry/closest_point.h"
#include "host/geometry/distance_stats.h"
#include "host/geometry/trimmed_face.h"

namespace dg::host {

struct PointDeviation {
  Point3 point;     // measured, mm
  Point3 foot;      // its closest surface point
  double distance;  // signed: positive on the side of S_u x S_v
  // The closest point lies on the surface's border and the point is off to the side of it
  // (beyond_edge, host/geometry/closest_point.h): its deviation is the distance to the edge, not
  // along a normal. B-spline surfaces and faces (their domain's edges), open meshes and CAD parts
  // (edges of one face or triangle); a closed mesh or a solid has none.
  bool beyond_edge = false;
};

struct Band {
  double limit_mm = 0;  // |deviation| <= limit
  size_t count = 0;
  double share = 0;  // count / points
};

struct Inspection {
  std::vector<PointDeviation> points;  // every point, those beyond the edge too
  // Of the points over the surface: a point beyond its edge has no deviation along a normal, so it
  // is counted in beyond_edge and left out of these (stats.count is the points over the surface).
  DistanceStats stats;
  std::vector<Band> bands;  // shares of the points over the surface
  size_t beyond_edge = 0;   // points marked beyond_edge
};

// Every point's closest point by SurfaceLocator; `bands_mm` in ascending order. Throws
// std::invalid_argument for no points, a point whose distance is not finite (naming it), or points
// that all lie beyond the surface's edge.
Inspection inspect(const std::vector<Point3>& points, const BSplineSurface& surface, const std::vector<double>& bands_mm);

// The same against trimmed faces: each point is measured to the face whose loops hold its XY, or,
// beyond every face, to the nearest face.
Inspection inspect_faces(const std::vector<Point3>& points, const std::vector<TrimmedFace>& faces,
                         const std::vector<double>& bands_mm);

// The same against any nominal that finds closest points: a mesh (MeshLocator), a CAD part's faces.
// With `concurrent`, `closest` is called from several threads at once (a MeshLocator may be; a CAD
// part's OpenCASCADE surfaces keep evaluation caches and may not).
Inspection inspect_nominal(const std::vector<Point3>& points, const std::function<Closest(const Point3&)>& closest,
                           const std::vector<double>& bands_mm, bool concurrent = false);

}  // namespace dg::host

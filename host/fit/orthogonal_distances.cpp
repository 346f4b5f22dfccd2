// Closest-point projection per point from the parameters the fit gave it: a few Gauss-Newton steps each.
#include "host/fit/orthogonal_distances.h"

#include "host/geometry/closest_point.h"

namespace dg::host {

std::vector<double> orthogonal_distances(const BSplineSurface& surface, const std::vector<Point3>& points,
                                         const Parameters& params) {
  std::vector<double> d(points.size());
  for (size_t k = 0; k < points.size(); ++k) d[k] = closest_point(surface, points[k], params.uv[k].u, params.uv[k].v).distance;
  return d;
}

}  // namespace dg::host

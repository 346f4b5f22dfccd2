// Deviations, statistics and band counts for a point set against a surface.
#include "host/inspect/inspect.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "host/geometry/surface_locator.h"

namespace dg::host {

Inspection inspect(const std::vector<Point3>& points, const BSplineSurface& surface, const std::vector<double>& bands_mm) {
  Inspection out;
  if (points.empty()) throw std::invalid_argument("there are no points to inspect");
  const SurfaceLocator locator(surface);
  out.points.reserve(points.size());
  std::vector<double> distances;
  distances.reserve(points.size());
  for (const Point3& p : points) {
    const Closest c = locator.closest(p);
    // A coordinate near the limits of a double (1e308) makes the distance overflow: no statistic
    // is printed from it.
    if (!std::isfinite(c.distance) || !std::isfinite(c.point.x + c.point.y + c.point.z)) {
      char where[160];
      std::snprintf(where, sizeof where, "point %zu (%.6g, %.6g, %.6g)", out.points.size() + 1, p.x, p.y, p.z);
      throw std::invalid_argument(std::string(where) +
                                  ": its distance to the surface is not a finite number; a coordinate that large is no measurement");
    }
    out.points.push_back({p, c.point, c.distance});
    distances.push_back(c.distance);
  }
  out.stats = distance_stats(distances);
  for (double limit : bands_mm) {
    Band band;
    band.limit_mm = limit;
    for (double d : distances) band.count += std::fabs(d) <= limit;
    band.share = points.empty() ? 0.0 : static_cast<double>(band.count) / static_cast<double>(points.size());
    out.bands.push_back(band);
  }
  return out;
}

}  // namespace dg::host

// Deviations, statistics and band counts for a point set against a surface.
#include "host/inspect/inspect.h"

#include <cmath>

#include "host/geometry/surface_locator.h"

namespace dg::host {

Inspection inspect(const std::vector<Point3>& points, const BSplineSurface& surface, const std::vector<double>& bands_mm) {
  Inspection out;
  const SurfaceLocator locator(surface);
  out.points.reserve(points.size());
  std::vector<double> distances;
  distances.reserve(points.size());
  for (const Point3& p : points) {
    const Closest c = locator.closest(p);
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

// Deviations, statistics and band counts for a point set against a surface.
#include "host/inspect/inspect.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "host/geometry/surface_locator.h"
#include "host/geometry/vec3.h"
#include "host/parallel/parallel_for.h"

namespace dg::host {

namespace {

// Every point's closest point by `closest(p)`, checked finite, with the statistics
// and bands; on every core when `concurrent` (each point's result has its own slot, so the results
// are those of one thread).
template <class Locate>
Inspection measure(const std::vector<Point3>& points, Locate closest, const std::vector<double>& bands_mm, bool concurrent) {
  Inspection out;
  if (points.empty()) throw std::invalid_argument("there are no points to inspect");
  out.points.resize(points.size());
  auto measure_range = [&](size_t begin, size_t end, unsigned) {
    for (size_t i = begin; i < end; ++i) {
      const dg::host::Closest c = closest(points[i]);
      out.points[i] = {points[i], c.point, c.distance, beyond_edge(points[i], c)};
    }
  };
  if (concurrent) {
    parallel_for(points.size(), measure_range);
  } else {
    measure_range(0, points.size(), 0);
  }
  for (size_t i = 0; i < points.size(); ++i) {
    const PointDeviation& d = out.points[i];
    // A coordinate near the limits of a double (1e308) makes the distance overflow: no statistic
    // is printed from it. The first such point is named, whichever thread measured it.
    if (!std::isfinite(d.distance) || !std::isfinite(d.foot.x + d.foot.y + d.foot.z)) {
      const Point3& p = points[i];
      char where[160];
      std::snprintf(where, sizeof where, "point %zu (%.6g, %.6g, %.6g)", i + 1, p.x, p.y, p.z);
      throw std::invalid_argument(std::string(where) +
                                  ": its distance to the surface is not a finite number; a coordinate that large is no measurement");
    }
  }
  // A point beyond the edge measures the distance to the edge, not the part's form there: the
  // statistics and bands are of the points over the surface only, and none are made from none.
  std::vector<double> over;
  over.reserve(points.size());
  for (const PointDeviation& d : out.points) {
    if (d.beyond_edge) ++out.beyond_edge;
    else over.push_back(d.distance);
  }
  if (over.empty()) {
    throw std::invalid_argument("every one of the " + std::to_string(points.size()) +
                                " points lies beyond the surface's edge, so none can be measured along a normal: are "
                                "they the points of this part, in its coordinates (else --align)?");
  }
  out.stats = distance_stats(over);
  for (double limit : bands_mm) {
    Band band;
    band.limit_mm = limit;
    for (double d : over) band.count += std::fabs(d) <= limit;
    band.share = static_cast<double>(band.count) / static_cast<double>(over.size());
    out.bands.push_back(band);
  }
  return out;
}

}  // namespace

Inspection inspect(const std::vector<Point3>& points, const BSplineSurface& surface, const std::vector<double>& bands_mm) {
  if (points.empty()) throw std::invalid_argument("there are no points to inspect");
  const SurfaceLocator locator(surface);
  return measure(points, [&](const Point3& p) { return locator.closest(p); }, bands_mm, true);
}

Inspection inspect_faces(const std::vector<Point3>& points, const std::vector<TrimmedFace>& faces,
                         const std::vector<double>& bands_mm) {
  if (points.empty()) throw std::invalid_argument("there are no points to inspect");
  if (faces.empty()) throw std::invalid_argument("there are no faces to inspect against");
  std::vector<SurfaceLocator> locators;
  for (const TrimmedFace& f : faces) locators.emplace_back(f.surface);
  return measure(
      points,
      [&](const Point3& p) {
        for (size_t k = 0; k < faces.size(); ++k) {
          if (inside_face(faces[k], p.x, p.y)) return locators[k].closest(p);
        }
        dg::host::Closest best = locators[0].closest(p);
        for (size_t k = 1; k < faces.size(); ++k) {
          const dg::host::Closest c = locators[k].closest(p);
          if (std::fabs(c.distance) < std::fabs(best.distance)) best = c;
        }
        return best;
      },
      bands_mm, true);
}

Inspection inspect_nominal(const std::vector<Point3>& points, const std::function<Closest(const Point3&)>& closest,
                           const std::vector<double>& bands_mm, bool concurrent) {
  return measure(points, closest, bands_mm, concurrent);
}

}  // namespace dg::host

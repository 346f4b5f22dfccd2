// Closest-point projection per point from the parameters the fit gave it: a few Gauss-Newton steps
// each, on the surface's power form for many points, on every core (each point has its own slot,
// so any number of threads gives the same values).
#include "host/fit/orthogonal_distances.h"

#include "host/geometry/closest_point.h"
#include "host/geometry/patch_form.h"
#include "host/parallel/parallel_for.h"

namespace dg::host {

namespace {

// Both overloads: each point's signed distance, and its start distance into `start` when given.
std::vector<double> distances(const BSplineSurface& surface, const std::vector<Point3>& points, const Parameters& params,
                              std::vector<double>* start) {
  std::vector<double> d(points.size());
  if (start) start->resize(points.size());
  with_fast_form(surface, 2 * points.size(), [&](const auto& form) {
    parallel_for(points.size(), [&](size_t begin, size_t end, unsigned) {
      for (size_t k = begin; k < end; ++k) {
        const Closest c = closest_point(form, points[k], params.uv[k].u, params.uv[k].v);
        d[k] = c.distance;
        if (start) (*start)[k] = c.start_distance;
      }
    }, 1024);
  });
  return d;
}

}  // namespace

std::vector<double> orthogonal_distances(const BSplineSurface& surface, const std::vector<Point3>& points,
                                         const Parameters& params) {
  return distances(surface, points, params, nullptr);
}

std::vector<double> orthogonal_distances(const BSplineSurface& surface, const std::vector<Point3>& points,
                                         const Parameters& params, std::vector<double>& start) {
  return distances(surface, points, params, &start);
}

}  // namespace dg::host

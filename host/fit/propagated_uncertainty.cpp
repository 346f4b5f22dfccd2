// Propagating the points' standard uncertainty through a least-squares fit's covariance.
#include "host/fit/propagated_uncertainty.h"

#include <cmath>
#include <cstdio>

#include "host/fit/bspline_fit.h"
#include "host/fit/fit_error.h"
#include "host/fit/noise_estimate.h"
#include "host/fit/orthogonal_distances.h"
#include "host/geometry/trimmed_face.h"
#include "host/scan/median.h"

namespace dg::host {

SurfaceUncertainty propagated_uncertainty(const PointCloud& cloud, const Parameters& params, const std::vector<double>* w,
                                          const BSplineSurface& surface, const std::vector<double>& distances,
                                          const LeastSquaresFit* kept) {
  double sigma = 0;
  std::string from;
  if (w && cloud.sigma) {
    sigma = median_of(*cloud.sigma);
    from = cloud.sigma_from + ", each point's own; the median is given";
  } else {
    const NoiseEstimate noise = estimate_gauge_noise(cloud, params);
    if (noise.reading_sigma_mm > 0) {
      sigma = noise.reading_sigma_mm;
      char text[160];
      std::snprintf(text, sizeof text, "noise estimated from the scan, %.4f mm, with the reading step %.4f mm", noise.sigma_mm,
                    noise.resolution_mm);
      from = text;
    } else {
      const size_t unknowns = static_cast<size_t>(surface.count_u) * surface.count_v;
      double sum = 0;
      for (double d : distances) sum += d * d;
      if (distances.size() > unknowns) sigma = std::sqrt(sum / static_cast<double>(distances.size() - unknowns));
      from = "residual RMS over n - p degrees of freedom";
    }
  }
  if (!(sigma > 0) || !std::isfinite(sigma)) return {};
  try {
    SurfaceUncertainty u = kept != nullptr ? fit_uncertainty(*kept, sigma) : fit_uncertainty(cloud.points, params, w, surface, sigma);
    u.sigma_from = from;
    return u;
  } catch (const FitError&) {
    return {};  // the net cannot be refitted from these points: no uncertainty to state
  }
}

std::string add_scan_to_device_fit(FittedSurface& device_fit, const PointCloud& scan, uint32_t device_points,
                                   uint32_t device_rejected) {
  if (scan.points.empty()) return "the scan holds no points";
  const BSplineSurface& s = device_fit.surface;
  Parameters params;
  params.kind = Parameterization::kTableXy;
  const Point3 low = s.evaluate(s.u_min(), s.v_min()), high = s.evaluate(s.u_max(), s.v_max());
  params.x_min = low.x, params.x_max = high.x, params.y_min = low.y, params.y_max = high.y;
  for (const Point3& p : scan.points) {
    double u = 0, v = 0;
    table_to_parameters(s, p.x, p.y, u, v);
    params.uv.push_back({u, v});
  }
  const std::vector<double> distances = orthogonal_distances(s, scan.points, params);
  device_fit.has_fit = true;
  device_fit.distance = distance_stats(distances);
  device_fit.noise_sigma_mm = estimate_gauge_noise(scan, params).sigma_mm;
  if (device_rejected > 0) {
    return "the device left " + std::to_string(device_rejected) + " points out of its fit, and the scan does not say which";
  }
  if (device_points != scan.points.size()) {
    return "the device fitted " + std::to_string(device_points) + " points, the scan holds " + std::to_string(scan.points.size());
  }
  device_fit.uncertainty = propagated_uncertainty(scan, params, nullptr, s, distances);
  return device_fit.uncertainty.computed ? "" : "no noise estimate for the scan, or its points leave a control point undetermined";
}

}  // namespace dg::host

// The repeatability and the reading step combined per point, as the header says.
#include "host/scan/scan_uncertainty.h"

#include <cmath>
#include <cstdio>

namespace dg::host {

ScanPointSigmas scan_point_sigmas(const ScanData& scan) {
  ScanPointSigmas out;
  if (!scan.repeatability) {
    out.from = "the scan has no repeatability measurement (scan --repeatability N)";
    return out;
  }
  const digitizer_Repeatability& r = *scan.repeatability;
  if (r.count < 2) {
    out.from = "the scan's repeatability record holds fewer than 2 readings";
    return out;
  }
  const double s_mm = r.stddev_nm * 1e-6;
  const double step_mm = scan.device ? scan.device->gauge_resolution_nm * 1e-6 : 0.0;
  const double base_sq = s_mm * s_mm + step_mm * step_mm / 12.0;
  if (!(base_sq > 0)) {
    out.from = "the scan's repeatability is 0 and its gauge's reading step is not recorded";
    return out;
  }
  const double spread_mm = scan.request ? scan.request->spread_tolerance_nm * 1e-6 : 0.0;
  const double flagged_sq = base_sq + 0.25 * spread_mm * spread_mm;
  size_t flagged = 0;
  out.sigma_mm.reserve(scan.points.size());
  for (const PointSample& p : scan.points) {
    const bool spread_high = (p.flags & digitizer_PointFlag_POINT_SPREAD_HIGH) != 0 && spread_mm > 0;
    flagged += spread_high ? 1 : 0;
    out.sigma_mm.push_back(std::sqrt(spread_high ? flagged_sq : base_sq));
  }
  char text[256];
  std::snprintf(text, sizeof text,
                "the scan's repeatability (s = %.4f mm over %u readings at x %.3f y %.3f mm) with the gauge's %.4f mm "
                "reading step%s",
                s_mm, r.count, r.x_nm * 1e-6, r.y_nm * 1e-6, step_mm,
                flagged ? ", widened where the samples disagreed" : "");
  out.from = text;
  return out;
}

}  // namespace dg::host

// Reading a fitted surface's uncertainty grid between its nodes.
#include "host/geometry/surface_uncertainty.h"

#include <algorithm>

namespace dg::host {

bool has_uncertainty_grid(const SurfaceUncertainty& u) {
  return u.computed && u.rows >= 2 && u.cols >= 2 && u.u_mm.size() == static_cast<size_t>(u.rows) * u.cols;
}

bool uncertainty_at(const SurfaceUncertainty& u, double a, double b, double& value) {
  if (!has_uncertainty_grid(u)) return false;
  const double gc = std::clamp(a, 0.0, 1.0) * (u.cols - 1), gr = std::clamp(b, 0.0, 1.0) * (u.rows - 1);
  const int c0 = std::clamp(static_cast<int>(gc), 0, u.cols - 2), r0 = std::clamp(static_cast<int>(gr), 0, u.rows - 2);
  const double fc = gc - c0, fr = gr - r0;
  double sum = 0, weight = 0;
  for (int dr = 0; dr <= 1; ++dr) {
    for (int dc = 0; dc <= 1; ++dc) {
      const double node = u.u_mm[static_cast<size_t>(r0 + dr) * u.cols + (c0 + dc)];
      const double w = (dr ? fr : 1 - fr) * (dc ? fc : 1 - fc);
      if (node == kOffFace) continue;
      sum += w * node;
      weight += w;
    }
  }
  if (!(weight > 1e-9)) return false;
  value = sum / weight;
  return true;
}

}  // namespace dg::host

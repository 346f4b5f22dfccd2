// The check that a fit's report holds only finite numbers before it is written or printed.
#include "host/geometry/fitted_surface.h"

#include <cmath>
#include <initializer_list>

namespace dg::host {

namespace {

// The first of `values` that is not finite, named `what`; "" when all are.
std::string first_of(std::initializer_list<double> values, const std::string& what) {
  for (double v : values) {
    if (!std::isfinite(v)) return what;
  }
  return "";
}

std::string in_surface(const BSplineSurface& s, const std::string& whose) {
  for (size_t k = 0; k < s.control.size(); ++k) {
    const Point3& p = s.control[k];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return whose + "control point " + std::to_string(k + 1);
  }
  return "";
}

std::string in_distances(const DistanceStats& d, const std::string& whose) {
  if (d.count == 0) return "";
  return first_of({d.mean, d.median, d.stddev, d.rms, d.max, d.min, d.max_abs}, whose + "orthogonal distances");
}

std::string in_uncertainty(const SurfaceUncertainty& u, const std::string& whose) {
  if (!u.computed) return "";
  std::string found = first_of({u.sigma_mm, u.max_mm, u.mean_mm}, whose + "uncertainty");
  for (size_t k = 0; found.empty() && k < u.u_mm.size(); ++k) {
    if (!std::isfinite(u.u_mm[k])) found = whose + "uncertainty grid";
  }
  return found;
}

}  // namespace

std::string non_finite_result(const FittedSurface& f) {
  std::string found = in_surface(f.surface, "the surface's ");
  if (found.empty()) found = in_distances(f.distance, "the points' ");
  if (found.empty()) found = first_of({f.tolerance_mm, f.noise_sigma_mm}, "the tolerance or the noise estimate");
  if (found.empty() && f.validation.checked) {
    const FitValidation& v = f.validation;
    if (v.held_out_points > 0) found = first_of({v.held_out_rms_mm, v.held_out_max_mm}, "the held-out points' errors");
    if (found.empty() && v.neighbour_checks > 0) found = first_of({v.range_excess_max_mm}, "the check between neighbouring samples");
  }
  if (found.empty()) found = in_uncertainty(f.uncertainty, "the surface's ");
  for (size_t k = 0; found.empty() && k < f.faces.size(); ++k) {
    const std::string face = "face " + std::to_string(k + 1) + "'s ";
    found = in_surface(f.faces[k].surface, face);
    if (found.empty()) found = in_distances(f.faces[k].distance, face);
    if (found.empty()) found = in_uncertainty(f.faces[k].uncertainty, face);
  }
  return found;
}

}  // namespace dg::host

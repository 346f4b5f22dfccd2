// Converting the device's FitResult (nm, Q-format solve) into the host's B-spline surface (mm).
#include "host/fit/device_fit_surface.h"

#include "host/fit/fit_error.h"

namespace dg::host {

FittedSurface surface_from_device_fit(const digitizer_FitResult& fit, const std::string& source) {
  switch (fit.status) {
    case digitizer_FitStatus_FIT_OK: break;
    case digitizer_FitStatus_FIT_NO_SCAN: throw FitError("the device has not scanned since it started: no fit to pull");
    case digitizer_FitStatus_FIT_TOO_FEW_POINTS:
      throw FitError("the device's fit has " + std::to_string(fit.points) + " points, fewer than its control points");
    case digitizer_FitStatus_FIT_UNDETERMINED:
      throw FitError("the device's points leave a control point undetermined (a single line, or a scan smaller than the net)");
    default: throw FitError("the device's fit has an unknown status " + std::to_string(fit.status));
  }
  const int side = static_cast<int>(fit.side);
  const bool bezier = fit.model == digitizer_DeviceFitModel_DEVICE_FIT_BEZIER;
  if (side < 4 || side > 8 || (bezier && side != 4) || fit.z_nm_count != static_cast<pb_size_t>(side * side)) {
    throw FitError("the device's fit is malformed: " + std::to_string(fit.z_nm_count) + " heights for side " +
                   std::to_string(side));
  }
  if (!fit.has_x || !fit.has_y || fit.x.max_nm <= fit.x.min_nm || fit.y.max_nm <= fit.y.min_nm) {
    throw FitError("the device's fit has an empty rectangle");
  }
  FittedSurface out;
  out.model = bezier ? "bezier" : "bspline";
  out.method = "device";
  out.parameterization = "xy";
  out.height_field = true;
  out.source = source;
  BSplineSurface& s = out.surface;
  s.count_u = s.count_v = side;
  if (bezier) {
    s.knots_u = s.knots_v = clamped_uniform_knots(4, 3);
  } else {
    for (int i = 0; i <= side + 3; ++i) s.knots_u.push_back(static_cast<double>(i - 3) / (side - 3));
    s.knots_v = s.knots_u;
  }
  const double x0 = fit.x.min_nm * 1e-6, dx = (static_cast<double>(fit.x.max_nm) - fit.x.min_nm) * 1e-6;
  const double y0 = fit.y.min_nm * 1e-6, dy = (static_cast<double>(fit.y.max_nm) - fit.y.min_nm) * 1e-6;
  s.control.resize(static_cast<size_t>(side * side));
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j) {
      s.at(i, j) = {x0 + dx * greville(s.knots_u, 3, i), y0 + dy * greville(s.knots_v, 3, j),
                    fit.z_nm[i * side + j] * 1e-6};
    }
  }
  return out;
}

}  // namespace dg::host

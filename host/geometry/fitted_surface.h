// A fitted surface as a value: the surface, the model and method that made it, and the fit's report.
#pragma once
#include <string>

#include "host/geometry/bspline_surface.h"
#include "host/geometry/distance_stats.h"

namespace dg::host {

struct FittedSurface {
  std::string model = "bspline";  // bspline | bezier
  std::string method = "lsq";     // lsq | ips | device
  std::string parameterization = "xy";
  bool height_field = true;
  BSplineSurface surface;
  // Fit report; `has_fit` false for a surface that was not fitted here.
  bool has_fit = false;
  DistanceStats distance;  // orthogonal distances, mm
  double tolerance_mm = 0;  // 0: no tolerance asked
  bool tolerance_kept = false;
  double noise_sigma_mm = 0;
  int iterations = 0;
  std::string source;  // the points file
};

}  // namespace dg::host

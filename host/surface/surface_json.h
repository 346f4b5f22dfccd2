// The surface file (SURF.json, docs/surface-json.md): model, degrees, knots, control net, fit statistics.
#pragma once
#include <string>

#include "host/surface/bspline_surface.h"
#include "host/surface/distance_stats.h"

namespace dg::host {

struct SurfaceFile {
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

// Throws std::runtime_error naming the file on I/O errors.
void write_surface_json(const std::string& path, const SurfaceFile& file);
std::string surface_json_text(const SurfaceFile& file);
// Throws std::runtime_error naming the file and what is wrong: malformed JSON, a missing or
// mistyped field, an invalid knot vector or net.
SurfaceFile read_surface_json(const std::string& path);
SurfaceFile parse_surface_json(const std::string& text, const std::string& name);

}  // namespace dg::host

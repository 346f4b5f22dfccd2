// Surface parameters (u, v) for measured points: table XY, or per scan line uniform/chord/centripetal.
#pragma once
#include <string>
#include <vector>

#include "host/scan/point_reader.h"

namespace dg::host {

enum class Parameterization { kTableXy, kUniform, kChordLength, kCentripetal };

Parameterization parse_parameterization(const std::string& name);  // throws FitError
const char* parameterization_name(Parameterization p);

struct UV {
  double u = 0, v = 0;
};

struct Parameters {
  Parameterization kind = Parameterization::kTableXy;
  std::vector<UV> uv;  // one per point, in [0, 1]^2
  // kTableXy: u = (x - x_min) / (x_max - x_min), v likewise; the surface is a height field.
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
};

// kTableXy works for scattered points. The others follow Koivunen and Bajcsy 1992, eq. 6-7 along each scan line (the
// `line` of the cloud; lines that run backwards, as in a serpentine scan, are reversed) and apply
// the same rule across lines to the distances between successive line centroids.
// Throws FitError for collinear points, a single line, or missing lines.
Parameters parameterize(const PointCloud& cloud, Parameterization kind);

}  // namespace dg::host

// Each point's deviation as a file: CSV for scripts and spreadsheets, or binary PLY with the
// deviation as a scalar field (CloudCompare's `scalar_` convention) so a point-cloud viewer colours it.
#pragma once
#include <string>
#include <vector>

#include "host/inspect/inspect.h"

namespace dg::host {

// "x,y,z,deviation,beyond_edge" in mm, six decimals; beyond_edge 1 for a point whose closest point
// is on the surface's edge and off to its side (PointDeviation), else 0.
std::string format_deviations_csv(const std::vector<PointDeviation>& points);
// Binary little-endian PLY: double x, y, z, float scalar_deviation (mm) and uchar
// scalar_beyond_edge (0 or 1) per vertex.
std::string format_deviations_ply(const std::vector<PointDeviation>& points);

}  // namespace dg::host

// Each point's deviation as a file: CSV for scripts and spreadsheets, or binary PLY with the
// deviation as a scalar field (CloudCompare's `scalar_` convention) so a point-cloud viewer colours it.
#pragma once
#include <string>
#include <vector>

#include "host/inspect/inspect.h"

namespace dg::host {

// "x,y,z,deviation" in mm, six decimals.
std::string format_deviations_csv(const std::vector<PointDeviation>& points);
// Binary little-endian PLY: double x, y, z and float scalar_deviation (mm) per vertex.
std::string format_deviations_ply(const std::vector<PointDeviation>& points);

}  // namespace dg::host

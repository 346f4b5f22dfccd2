// The table's travel error measured on a flat: a scan of an optical flat or a surface plate on a
// regular grid becomes the map of a TableCalibration.
#pragma once
#include <string>

#include "host/scan/point_reader.h"
#include "host/scan/table_calibration.h"

namespace dg::host {

// The flat's readings less their best plane (the flat's tilt and height on the table are its setup,
// not the machine's; a tilt of the travel itself cannot be told from it with one placement), each
// node smoothed by a quadratic through its 5 x 5 grid neighbours (shifted inward at the edges) so
// that the map carries less than the gauge's noise. Each node's u combines that fit's noise,
// sigma sqrt([(X^T X)^-1]_00), and the flat's certified flatness as a rectangular distribution
// (F / 2 / sqrt 3, GUM 4.3.7). Needs every node of a regular grid of at least 5 x 5 points; throws
// CalibrationError naming what is missing.
TableCalibration calibrate_from_flat(const PointCloud& flat, double flatness_mm, const std::string& name);

}  // namespace dg::host

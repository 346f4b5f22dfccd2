// Maps of a value per measured point over the part's XY extent (deviation heat maps and Hamdan's (2010)
// X, Y and Z error maps), as PNG and as SVG, with a colour bar in millimetres.
#pragma once
#include <string>
#include <vector>

#include "host/inspect/raster.h"

namespace dg::host {

struct MapPoint {
  double x_mm = 0, y_mm = 0;  // where on the table
  double value_mm = 0;        // what the colour shows
};

struct MapPicture {
  int width = 900, height = 600;
  double range_mm = 0;  // colours span [-range, +range]; 0: the largest |value|
  // A value that is never negative (an uncertainty): white at 0 to red at +range, the bar from 0.
  bool magnitude = false;
};

// Blue (negative) through white (0) to red (positive); t in [-1, 1], clamped.
Rgb diverging_colour(double t);

// The points are binned into cells a few pixels wide and each cell shows its largest |value|, so
// one bad point stays visible among a million. Empty input gives an empty plot with its bar.
std::string deviation_map_png(const std::vector<MapPoint>& points, const MapPicture& picture);
std::string deviation_map_svg(const std::vector<MapPoint>& points, const MapPicture& picture, const std::string& title);

}  // namespace dg::host

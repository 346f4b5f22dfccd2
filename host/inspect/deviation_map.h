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
  // Drawn in kMutedColour, off the scale and not stretching it: a point whose value is no measure
  // of what the map shows (one beyond the surface's edge, its distance to the edge).
  bool muted = false;
};
constexpr Rgb kMutedColour{150, 150, 150};

// How a value becomes a colour: one scale for a map, its colour bar and the 3D view.
struct ColourScale {
  double range_mm = 0;  // diverging colours span [-range, +range]; 0: the largest |value|
  // A value that is never negative (an uncertainty): white at 0 to red at +range, the bar from 0.
  bool magnitude = false;
  // A tolerance's limits on the signed value: when lower < upper, the tolerance scale
  // (tolerance_colour) instead, whatever the range.
  double lower_mm = 0, upper_mm = 0;
  bool tolerance() const { return lower_mm < upper_mm; }
};

struct MapPicture {
  int width = 900, height = 600;
  ColourScale scale;
};

// Blue (negative) through white (0) to red (positive); t in [-1, 1], clamped.
Rgb diverging_colour(double t);

// The tolerance scale, as inspection reports draw a profile tolerance: green about the nominal (0,
// or the middle of limits that do not straddle it), graded through yellow to red at the upper
// limit and through cyan to blue at the lower one; beyond the limits two colours the ramp never
// takes, magenta above and dark violet below, so a point out of tolerance cannot pass for one near
// a limit. A value on a limit is inside.
Rgb tolerance_colour(double value_mm, double lower_mm, double upper_mm);
constexpr Rgb kAboveUpperLimit{200, 20, 200}, kBelowLowerLimit{85, 20, 110};

// The colour of `value_mm` on `scale`, `range_mm` being its range resolved (> 0).
Rgb scale_colour(const ColourScale& scale, double range_mm, double value_mm);

// The points are binned into cells a few pixels wide and each cell shows its largest |value|, so
// one bad point stays visible among a million; a cell of muted points only is grey. Empty input gives an empty plot with its bar.
std::string deviation_map_png(const std::vector<MapPoint>& points, const MapPicture& picture);
std::string deviation_map_svg(const std::vector<MapPoint>& points, const MapPicture& picture, const std::string& title);

}  // namespace dg::host

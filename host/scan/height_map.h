// Height maps: a scan on an even grid as the autolevel files of bench users' other tools, bCNC
// (.probe), Candle (.map) and Klipper (a bed_mesh profile), written and read.
#pragma once
#include <string>
#include <vector>

#include "host/geometry/point3.h"
#include "host/scan/point_reader.h"

namespace dg::host {

struct HeightMap {
  double min_x_mm = 0, max_x_mm = 0, min_y_mm = 0, max_y_mm = 0;
  int count_x = 0, count_y = 0;
  std::vector<double> z_mm;  // row after row from min_y, each from min_x: z_mm[j * count_x + i]

  double step_x_mm() const { return (max_x_mm - min_x_mm) / (count_x - 1); }
  double step_y_mm() const { return (max_y_mm - min_y_mm) / (count_y - 1); }
  double z(int i, int j) const { return z_mm[static_cast<size_t>(j) * count_x + i]; }
  std::vector<Point3> points() const;
};

// The grid the points lie on: evenly spaced x and y positions (to a hundredth of a step), every
// node holding exactly one point. Throws std::invalid_argument naming `name` and the first node
// that is missing, held twice, or off the grid (a scan that stopped early, a scattered cloud).
HeightMap height_map_from_points(const std::vector<Point3>& points, const std::string& name);

// bCNC's autolevel file (its Probe.save): "xmin xmax xn", "ymin ymax yn", "zmin zmax feed" (the
// probing range and feed, here the heights' range and 0), then "x y z" per node, row by row.
std::string format_bcnc_probe(const HeightMap& map);
// Candle's height map (its saveHeightMap), CRLF lines of ';'-separated fields: the border
// "x;y;width;height", the grid "points_x;points_y;z_bottom;z_top", the interpolation
// "type;points_x;points_y" (0, bicubic, at the grid's own points), then one line of heights per
// row from min_y.
std::string format_candle_map(const HeightMap& map);
// A Klipper bed_mesh profile block as SAVE_CONFIG writes it at the end of printer.cfg: `#*#
// [bed_mesh NAME]`, version 1, the points row by row from min_y, x_count, y_count, min/max x/y,
// mesh_x_pps and mesh_y_pps 2, algo bicubic (lagrange below 4 points a side) and tension 0.2.
// Klipper takes at least 3 points a side: fewer throw std::invalid_argument.
std::string format_klipper_mesh(const HeightMap& map, const std::string& profile);

// The readers of the same files (a Klipper profile is found among the rest of a printer.cfg; the
// first bed_mesh profile is read). Throw PointFileError naming `name` and the line.
HeightMap parse_bcnc_probe(const std::string& text, const std::string& name);
HeightMap parse_candle_map(const std::string& text, const std::string& name);
HeightMap parse_klipper_mesh(const std::string& text, const std::string& name);

}  // namespace dg::host

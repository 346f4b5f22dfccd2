// Writing measured points as CSV (x,y,z,line in mm) and binary PLY.
#pragma once
#include <string>
#include <vector>

#include "common/proto/point_batch.h"
#include "host/geometry/point3.h"
#include "host/io/file_name.h"

namespace dg::host {

// Millimetres with six decimals: exact to the nanometre the device measured.
void write_points_csv(const std::string& path, const std::vector<PointSample>& points);
// Whitespace XYZ: "x y z" in mm a line, six decimals (what many CAD and mesh programs import).
void write_points_xyz(const std::string& path, const std::vector<PointSample>& points);
// Binary little-endian PLY: double x, y, z (mm) and int line, one vertex per point.
void write_points_ply(const std::string& path, const std::vector<PointSample>& points);
// Writes points in mm with their line index as CSV (x,y,z,line), to 0.1 nm.
void write_lines_csv(const std::string& path, const std::vector<Point3>& points,
                     const std::vector<uint32_t>& lines);
// The same with the line column only when `lines` is given.
void write_cloud_csv(const std::string& path, const std::vector<Point3>& points, const std::vector<uint32_t>* lines);
// Picks the format from the extension (.csv, .xyz, .ply); throws std::invalid_argument otherwise.
void write_points(const std::string& path, const std::vector<PointSample>& points);
// The same in `format` (kCsv, kXyz or kPly) whatever the extension.
void write_points(const std::string& path, const std::vector<PointSample>& points, FileFormat format);

}  // namespace dg::host

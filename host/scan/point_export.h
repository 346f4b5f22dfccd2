// Writing measured points as CSV (x,y,z,line in mm) and binary PLY.
#pragma once
#include <string>
#include <vector>

#include "common/proto/point_batch.h"
#include "host/geometry/point3.h"
#include "host/io/file_name.h"

namespace dg::host {

// Millimetres with six decimals: exact to the nanometre the device measured. With `sigma_mm` (one
// per point: a scan's per-point standard uncertainty) a sigma column follows, which every reader of
// a CSV takes as the points' uncertainty.
void write_points_csv(const std::string& path, const std::vector<PointSample>& points,
                      const std::vector<double>* sigma_mm = nullptr);
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
// The same in `format` (kCsv, kXyz or kPly) whatever the extension; `sigma_mm` as for CSV (the
// other formats have no column for it).
void write_points(const std::string& path, const std::vector<PointSample>& points, FileFormat format,
                  const std::vector<double>* sigma_mm = nullptr);

}  // namespace dg::host

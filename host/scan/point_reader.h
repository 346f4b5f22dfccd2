// Reading point clouds in millimetres: CSV with a header, whitespace XYZ, PLY and scan files.
#pragma once
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "host/geometry/point3.h"

namespace dg::host {

// Bad input: the message names the file and the line.
class PointFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PointCloud {
  std::vector<Point3> points;                 // mm
  std::optional<std::vector<uint32_t>> line;  // from a `line` column or a scan file
  std::optional<std::vector<Point3>> normal;  // from nx,ny,nz
  std::optional<std::vector<double>> sigma;   // per-point standard uncertainty, mm
  std::string sigma_from = "the points' sigma column";  // where `sigma` came from, for reports
  std::optional<double> resolution_mm;        // the gauge's reading step, when the file says it
  std::string calibration;                    // the table calibration that corrected z ("" none)
  std::string drift;                          // how the gauge's drift was removed ("" not)
  std::string fly;                            // a fly scan's latch delay and lifted points ("" not one)
};

// Picks the reader by extension: .csv, .xyz/.txt, .ply, .scan, and the height maps .probe (bCNC),
// .map (Candle) and .cfg (a Klipper bed_mesh profile). Throws PointFileError for
// NaN, infinity, short or long rows, unknown or repeated columns, repeated points.
// A scan file's points come corrected for the gauge's drift (by its reference readings, which are
// not points) and by its calibration record, if it has them; `as_measured` leaves them as the
// device measured them (for the device's own fit, which was made of those).
PointCloud read_points(const std::string& path, bool as_measured = false);

// A `line` column's value as a line number: a whole number from 0 to 4294967294 (4294967295,
// UINT32_MAX, is kept for "no line" by the code that reads lines); false for any other value.
inline bool line_number_of(double value, uint32_t& line) {
  if (!(value >= 0 && value == std::floor(value) && value <= 4294967294.0)) return false;
  line = static_cast<uint32_t>(value);
  return true;
}
inline constexpr const char* kLineNumberRule = "line must be a whole number from 0 to 4294967294";
// A coordinate (x, y, z in mm) or a normal's component read lies within +-kCoordinateLimitMm: a
// kilometre is far beyond any part a bench instrument measures, and within it the squares and
// products the fits form stay far from overflow (a z of 1e200 mm made every distance of a fit
// infinite, and `fit` wrote them as null and ended with success).
inline constexpr double kCoordinateLimitMm = 1e6;
inline bool plausible_coordinate(double value) { return std::fabs(value) <= kCoordinateLimitMm; }
inline constexpr const char* kCoordinateRule = "coordinates and normals must lie within +-1000000 mm (1 km)";
// A `sigma` column's value is a standard uncertainty: from a nanometre to a kilometre. A point of
// 1e-12 mm among points of 0.001 weighed 1e18 times as much, and the fit took it for a hole in the
// scan.
inline bool valid_sigma(double value) { return value >= 1e-6 && value <= kCoordinateLimitMm; }
inline constexpr const char* kSigmaRule = "sigma must be from 0.000001 to 1000000 mm (1 nm to 1 km)";
PointCloud parse_csv_points(std::string_view text, const std::string& name);
PointCloud parse_xyz_points(std::string_view text, const std::string& name);
// Throws for a point that repeats an earlier one; where_is(i) names point i ("in.csv:12").
void check_duplicate_points(const PointCloud& cloud, const std::function<std::string(size_t)>& where_is);

}  // namespace dg::host

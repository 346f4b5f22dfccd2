// IGES 5.3 output of a B-spline surface: entity 128 (rational B-spline surface) in millimetres.
#pragma once
#include <string>

#include "host/surface/bspline_surface.h"

namespace dg::host {

struct IgesOptions {
  std::string file_name = "surface.igs";
  std::string timestamp = "20260101.000000";  // YYYYMMDD.HHNNSS, the file's creation time
  std::string author = "bench digitizer";
  std::string organization = "bench digitizer";
  double resolution_mm = 1e-4;  // the smallest distance the model means to resolve
};

// The whole file: start, global (millimetres, sender "bench digitizer", IGES 5.3), one directory
// entry and the parameter data of entity 128, and the terminate line, in the fixed 80-column layout.
// Our surfaces are polynomial: every weight is 1 and PROP3 says so. Throws std::invalid_argument
// for a surface that is_valid() rejects.
std::string iges_text(const BSplineSurface& surface, const IgesOptions& options);
void write_iges(const std::string& path, const BSplineSurface& surface, const IgesOptions& options);

// An IGES real: shortest round-trip digits with a decimal point and an upper-case exponent.
std::string iges_real(double value);

}  // namespace dg::host

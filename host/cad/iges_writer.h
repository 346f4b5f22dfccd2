// IGES 5.3 output in millimetres: a B-spline surface as entity 128, curves as entity 126.
#pragma once
#include <string>

#include <vector>

#include "host/geometry/bspline_curve.h"
#include "host/geometry/bspline_surface.h"
#include "host/geometry/trimmed_face.h"

namespace dg::host {

struct IgesOptions {
  std::string file_name = "surface.igs";
  std::string product = "surface";  // the part's name: the product identification of sender and receiver
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

// Trimmed faces as entity 144 (IGES 5.3 section 4.34): each face's surface (128), and each of its
// loops as a curve on that surface (142, section 4.32) made of the loop in the surface's parameter
// space (126, planar, degree 1) and the same loop on the surface in model space (126, the surface
// points above the loop's vertices, edges cut to 0.25 mm); the parameter-space curve is the
// preferred one. The outer loop bounds the face, the others are holes.
std::string iges_faces_text(const std::vector<TrimmedFace>& faces, const IgesOptions& options);
void write_iges_faces(const std::string& path, const std::vector<TrimmedFace>& faces, const IgesOptions& options);

// Curves as entity 126 (rational B-spline curve, all weights 1, marked polynomial and non-planar).
std::string iges_curves_text(const std::vector<BSplineCurve>& curves, const IgesOptions& options);
void write_iges_curves(const std::string& path, const std::vector<BSplineCurve>& curves, const IgesOptions& options);

// An IGES real: shortest round-trip digits with a decimal point and an upper-case exponent.
std::string iges_real(double value);

}  // namespace dg::host

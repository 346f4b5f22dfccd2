// STEP (ISO 10303-21, AP214) output in millimetres: a B-spline surface as the face of an open shell
// in a shell-based surface model, or B-spline curves as a geometric curve set.
#pragma once
#include <string>

#include <vector>

#include "host/geometry/bspline_curve.h"
#include "host/geometry/bspline_surface.h"
#include "host/geometry/trimmed_face.h"

namespace dg::host {

struct StepOptions {
  std::string file_name = "surface.stp";
  std::string timestamp = "2026-01-01T00:00:00";  // ISO 8601, the file's creation time
  std::string product = "surface";
  double uncertainty_mm = 1e-4;
};

// The whole exchange file. The surface is clamped first (clamp_ends), its four edges become
// B-spline curves bounding one ADVANCED_FACE. Throws std::invalid_argument for an invalid surface.
std::string step_text(const BSplineSurface& surface, const StepOptions& options);
void write_step(const std::string& path, const BSplineSurface& surface, const StepOptions& options);

// Curves as B_SPLINE_CURVE_WITH_KNOTS in a GEOMETRIC_CURVE_SET (a wireframe representation).
// Trimmed faces: an open shell of advanced faces (a shell-based surface model, AP214), each face's
// surface bounded by its loops, each loop one closed edge on the surface (a degree-1 curve through
// the surface points above the loop's vertices, edges cut to 0.25 mm).
std::string step_faces_text(const std::vector<TrimmedFace>& faces, const StepOptions& options);
void write_step_faces(const std::string& path, const std::vector<TrimmedFace>& faces, const StepOptions& options);

std::string step_curves_text(const std::vector<BSplineCurve>& curves, const StepOptions& options);
void write_step_curves(const std::string& path, const std::vector<BSplineCurve>& curves, const StepOptions& options);

}  // namespace dg::host

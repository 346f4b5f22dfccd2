// A fitted surface as a value: the surface, the model and method that made it, and the fit's report.
#pragma once
#include <string>

#include "host/geometry/bspline_surface.h"
#include "host/geometry/distance_stats.h"
#include "host/geometry/surface_uncertainty.h"
#include "host/geometry/trimmed_face.h"

namespace dg::host {

// What the fit's validation between the samples found (host/fit/fit_validation.h).
struct FitValidation {
  bool checked = false;
  bool passed = false;  // with a tolerance: both checks held
  std::string problem;  // why it failed, or why it could not be validated
  // Hold-out: the points of each fold predicted by a surface fitted without them.
  int folds = 0;
  bool folds_of_lines = true;  // a fold is every folds-th scan line; false: every folds-th point (no lines)
  size_t held_out_points = 0;
  double held_out_rms_mm = 0, held_out_max_mm = 0;
  Point3 held_out_worst;  // the measured point predicted worst
  // Neighbours: how far the surface leaves the box of neighbouring samples (0 when it never does).
  size_t neighbour_checks = 0;
  double range_excess_max_mm = 0;
  Point3 range_worst;  // the surface point that leaves the box most
};

struct FittedSurface {
  std::string model = "bspline";  // bspline | bezier
  std::string method = "lsq";     // lsq | ips | device
  std::string parameterization = "xy";
  bool height_field = true;
  // One surface over the whole scan, or (faces not empty) several trimmed faces, one per region
  // between creases and steps (host/fit/regions.h); `surface` is then empty and unused.
  BSplineSurface surface;
  std::vector<TrimmedFace> faces;
  // A nominal that is no B-spline (a mesh, a CAD part's faces): what it is, for the report;
  // `surface` is then empty and unused.
  std::string nominal_summary;
  // Fit report; `has_fit` false for a surface that was not fitted here.
  bool has_fit = false;
  DistanceStats distance;  // orthogonal distances, mm
  double tolerance_mm = 0;  // 0: no tolerance asked
  bool tolerance_kept = false;
  double noise_sigma_mm = 0;
  int iterations = 0;
  std::string source;  // the points file
  FitValidation validation;
  SurfaceUncertainty uncertainty;
};

// What in a fit's numbers is not finite (an overflow, a NaN from a degenerate step), named for a
// message ("the points' orthogonal distances", "face 2's control point 7"); "" when all are finite.
// write_surface_json writes no fit that holds one, and `fit` and the device's fit print their
// summaries only after writing.
std::string non_finite_result(const FittedSurface& fit);

}  // namespace dg::host

// Fitting to a tolerance: refine a B-spline by knot insertion until every point is within it, or refuse.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "host/scan/point_reader.h"
#include "host/fit/bspline_fit.h"
#include "host/geometry/fitted_surface.h"

namespace dg::host {

struct ToleranceOptions {
  double tolerance_mm = 0.01;
  int degree_u = 3, degree_v = 3;
  int start_count_u = 0, start_count_v = 0;  // 0: degree + 1 (one Bezier patch)
  int max_iterations = 24;
  std::vector<double> extra_knots_u, extra_knots_v;  // knots that must stay (creases), parameters
  // Above this many points the loop first refines on an evenly strided sample of a quarter as many
  // and continues from its knots with every point (coarse nets need few points; the contract is
  // still judged on all of them).
  size_t sample_above = 400000;
  // Hold-out folds for the validation between the samples (fit_validation.h).
  int validation_folds = 5;
  // A region's points (host/fit/regions.h) over a larger box: control points beyond them are placed,
  // not fitted (LsqSpec::fill_outside).
  bool fill_outside = false;
  // Each point's place in its file (from 0), when the caller reordered the cloud (spatial_order.h):
  // a refusal names the point by it. Null: the cloud is in the file's order.
  const std::vector<uint32_t>* point_numbers = nullptr;
};

struct ToleranceResult {
  BSplineSurface surface;         // the best surface found (the last one when kept)
  bool kept = false;              // every orthogonal distance <= tolerance
  std::string reason;             // why it was refused, when not kept
  std::string note;               // when kept: why refinement stopped short of the noise, if it did
  double max_distance_mm = 0;     // largest orthogonal distance of `surface`
  double noise_sigma_mm = 0;      // estimated gauge noise (rounding to the reading step taken out)
  double resolution_mm = 0;       // the reading step it knew of
  double rms_mm = 0;              // RMS residual along the parameter direction (z for a height field)
  int iterations = 0;
  FitValidation validation;       // the checks between the samples, when the samples kept the tolerance
  std::vector<double> distances;  // signed orthogonal distances of `surface`
};

// Koivunen and Bajcsy 1992, section 5.4's refinement: start coarse, fit, and insert a knot in the middle of every
// knot span (in u and in v) that holds a point farther than the tolerance; repeat. The test is the
// maximum orthogonal distance: the cheap same-parameter distance bounds it from above, so only the
// points it does not clear are projected. Stops and refuses, with the best surface and the reason,
// when the residual is down to the estimated noise (more knots would fit noise), when refinement no
// longer improves, or when the points cannot support more knots.
ToleranceResult fit_to_tolerance(const PointCloud& cloud, const Parameters& params, const std::vector<double>* weights,
                                 const ToleranceOptions& options);

}  // namespace dg::host

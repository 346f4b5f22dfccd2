// The Least-Trimmed-Squares noise filter of Koivunen and Bajcsy 1992, section 5.2, for gridded and scattered scans.
#pragma once
#include <cstddef>
#include <vector>

#include "host/geometry/point3.h"

namespace dg::host {

// The fewest points the filter judges: one window of the smallest size it has, 3 x 3.
constexpr size_t kLtsFewestPoints = 9;

struct LtsOptions {
  int window = 5;           // grid: window x window neighbours; scattered: window^2 nearest
  int order = 2;            // 0: constant (the paper's p = 1); 1: plane (p = 3); 2: quadratic (p = 6)
  int h = 0;                // residuals kept; 0: [n/2] + [(p+1)/2]: 13 of 25 for p = 1, 14 for 3, 15 for 6
  bool replace_all = false;  // true: every point becomes the estimate (smoothing); false: outliers only
  int max_iterations = 50;
  double converged_mm = 1e-6;  // stop when no height changes by more than this
  // |z - filtered| above this many robust sigmas is reported. The scale comes from residuals to
  // estimates that include the point itself, which shrinks it; 5 keeps Gaussian points unflagged.
  double outlier_sigmas = 5.0;
  // The gauge's reading step in mm: negative to find it in the heights (detect_resolution_mm), 0
  // for unrounded readings. A reading rounded to a step q is uncertain by q / sqrt(12) however
  // repeatable it is (a rectangular distribution of half-width q / 2, as the GUM takes a
  // resolution), and the noise judged by is never taken below that.
  double resolution_mm = -1;
};

struct LtsOutlier {
  size_t index;
  double residual_mm;  // measured z - filtered z
};

struct LtsResult {
  std::vector<double> z;  // filtered heights, one per point, mm
  std::vector<LtsOutlier> outliers;
  // Points where no model of their neighbours describes the surface (steeper or more curved than
  // the grid resolves), whether a judge condemned them or not: kept with their measured heights,
  // since an outlier there cannot be told from the part's shape, nor a clean point cleared. Grids
  // only.
  std::vector<size_t> unjudged;
  bool gridded = false;   // the points formed a regular XY grid
  int iterations = 0;
  bool converged = false;
  size_t alternating = 0;  // not converged: this many points kept alternating when it stopped
  double sigma_mm = 0;    // robust scale of the residuals, at least the reading step's
  double resolution_mm = 0;  // the reading step used (0: none)
  bool sigma_is_resolution = false;  // the residuals scattered less than the reading step's q / sqrt(12)
};

// Filters z. Points on a regular XY grid (every x and y on multiples of one step, holes allowed
// but a point in at least a quarter of the cells)
// use the window x window grid neighbourhood; other points the window^2 nearest points in XY.
// In each neighbourhood the reference (first the median, then the previous iteration's output)
// picks the h heights nearest to it; order 0 takes their mean (Koivunen and Bajcsy 1992, section 5.2 exactly), orders
// 1 and 2 fit a plane or a quadratic to them, refine the subset by concentration steps (keep the h
// smallest residuals, refit) and take the model's value at the point. Iterated until no estimate
// changes by more than `converged_mm`, in floating point as the paper prescribes.
// Two departures from the paper, both measured on simulated 1 mm scans with 2 um noise: a constant
// (and even a plane) model is biased where the part curves or the window is one-sided (0.6 mm at
// the edge of a dome, 17 um median on a concave canister face), so the default model is quadratic;
// and by default only outliers are replaced by the estimate while inliers keep their measured
// heights, because the least-squares fit averages Gaussian noise without that bias.
LtsResult lts_filter(const std::vector<Point3>& points, const LtsOptions& options);

}  // namespace dg::host

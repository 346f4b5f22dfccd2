// Least-squares B-spline surfaces of any degree for scattered points (Koivunen and Bajcsy 1992, section 5.4).
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "host/geometry/bspline_surface.h"
#include "host/fit/parameterize.h"
#include "host/fit/site_index.h"
#include "host/geometry/fitted_surface.h"

namespace dg::host {

struct LsqSpec {
  int degree_u = 3, degree_v = 3;
  std::vector<double> knots_u, knots_v;  // clamped, on [0, 1]
  // For a region's trimmed surface (host/fit/regions.h): control points whose basis reaches no more
  // than 1 % at any point (outside_control_points) are not refused but placed by a membrane between neighbouring control
  // points (weight 1e-8 of the largest diagonal entry, so the fitted ones move by far less than a
  // nanometre). They shape the surface only beyond the region's points, where the trim cuts it off.
  // The other control points must still each have a point of their own (the tensor matching).
  bool fill_outside = false;
  // The basis value below which a control point counts as outside (knot_support.h's
  // outside_control_points); 0 fits every control point that any point touches.
  double outside_below = 0.01;
  // The points' SiteIndex when the caller has one for this very params.uv (a refinement loop fits
  // the same points many times); the fit builds its own otherwise.
  const SiteIndex* sites = nullptr;
};

// Solves Koivunen and Bajcsy 1992, eq. 8, C^T C B = C^T S, without forming C: each point adds the outer product of
// its (degree_u + 1)(degree_v + 1) non-zero basis values to a band of the normal matrix, which Eigen's
// sparse LDL^T then solves. `weights` (1 / sigma^2, optional) weight each point. For the table-XY
// parameterization the surface is a height field: x and y of the control points are fixed at the
// Greville abscissae (so S(u, v) lies exactly above the point) and only z is fitted.
// Nothing regularizes the solution. Throws FitError when the points cannot determine the net: fewer
// points than control points, a row or column of control points whose support holds no point, a
// direction that fails the Schoenberg-Whitney condition (more control points than distinct scan
// lines or positions can determine), or a vanishing pivot (a hole the net spans).
BSplineSurface fit_least_squares(const std::vector<Point3>& points, const Parameters& params,
                                 const std::vector<double>* weights, const LsqSpec& spec);

// The factored normal equations of a fit (bspline_fit.cpp).
struct NormalSystem;

// A fit kept with its factored normal equations: its uncertainty (fit_uncertainty below) then
// needs no second pass over the points and no second factorization.
struct LeastSquaresFit {
  BSplineSurface surface;
  std::shared_ptr<const NormalSystem> system;
  bool weighted = false;  // fitted with weights 1 / sigma_i^2
};
LeastSquaresFit fit_least_squares_kept(const std::vector<Point3>& points, const Parameters& params,
                                       const std::vector<double>* weights, const LsqSpec& spec);

// The net of `spec` fitted again without each validation fold's points (fold[k] = f: point k is
// left out of refit f; -1: in every refit), all from one pass over the points: the normal equations
// are sums over the points, so a refit's are the sums of the other folds'. kept_sites[f] indexes
// the points that remain in refit f (FoldSupport). A refit its points cannot determine comes back
// with the reason in `error` and no surface. Where the folds' sums would take more than
// `one_pass_bytes` (very large nets), each refit makes a pass of its own over the points instead.
struct FoldRefit {
  BSplineSurface surface;
  std::string error;
};
std::vector<FoldRefit> fit_least_squares_by_folds(const std::vector<Point3>& points, const Parameters& params,
                                                  const std::vector<double>* weights, const LsqSpec& spec,
                                                  const std::vector<int>& fold,
                                                  const std::vector<const SiteIndex*>& kept_sites,
                                                  size_t one_pass_bytes = size_t{256} << 20);

// The whole fit and its validation folds' refits (fit_least_squares_by_folds) from one pass over the
// points: the whole fit's sums are the folds' together. Throws FitError as fit_least_squares does
// when the points cannot determine the net; a refit that cannot be made has its reason.
struct FoldedFit {
  LeastSquaresFit fit;
  std::vector<FoldRefit> refits;
};
FoldedFit fit_least_squares_with_folds(const std::vector<Point3>& points, const Parameters& params,
                                       const std::vector<double>* weights, const LsqSpec& spec,
                                       const std::vector<int>& fold, const std::vector<const SiteIndex*>& kept_sites,
                                       size_t one_pass_bytes = size_t{256} << 20);

// The standard uncertainty of the fitted surface from the points' noise: the coefficients' covariance
// (C^T W C)^-1 (weights 1 / sigma_i^2) or sigma^2 (C^T C)^-1 (no weights, points of standard
// uncertainty `sigma_mm`) propagated to S(u, v) on a grid x grid over the parameter domain:
// u(u, v)^2 = b(u, v)^T Cov b(u, v), b the basis values there. It is the fit's precision (what
// repeating the scan would scatter), not its shape error, which the tolerance and the validation
// between the samples bound. The same net must be refittable from the points (FitError otherwise).
SurfaceUncertainty fit_uncertainty(const std::vector<Point3>& points, const Parameters& params,
                                   const std::vector<double>* weights, const BSplineSurface& surface, double sigma_mm,
                                   int grid = 21);
// The same for a kept fit, from the equations it was solved from.
SurfaceUncertainty fit_uncertainty(const LeastSquaresFit& fit, double sigma_mm, int grid = 21);

// The same for a region's net (LsqSpec::fill_outside): its coefficients are K^-1 C^T W z with
// K = C^T W C + the membrane, so their covariance is the sandwich K^-1 (C^T W C) K^-1 (times
// sigma^2 without weights), which carries the placed control points' dependence on the fitted
// ones. Only the grid nodes `counts(u, v)` accepts (inside the trimmed face) enter max and mean;
// the others are left 0 and are no figure.
SurfaceUncertainty region_fit_uncertainty(const std::vector<Point3>& points, const Parameters& params,
                                          const std::vector<double>* weights, const BSplineSurface& surface,
                                          double sigma_mm, int grid, const std::function<bool(double, double)>& counts);

// Distance from each point to the surface point with the same parameters: an upper bound of the
// orthogonal distance, cheap enough to screen millions of points.
std::vector<double> parameter_distances(const BSplineSurface& surface, const std::vector<Point3>& points,
                                        const Parameters& params);

}  // namespace dg::host

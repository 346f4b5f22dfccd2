// The standard uncertainty of a least-squares surface, propagated from its points' own: for a fit
// made here, and for the fit a device made of the points it sent.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "host/fit/bspline_fit.h"
#include "host/fit/parameterize.h"
#include "host/geometry/fitted_surface.h"
#include "host/scan/point_reader.h"

namespace dg::host {

// From the sigma column when the fit was weighted by it (`w`), else the noise estimate (the
// readings' scatter, rounding included), else the residual RMS over n - p (`distances`). Not
// computed (computed false) when no sigma can be stated or the net cannot be refitted. `kept`,
// when given, is the fit `surface` came from, with its equations: they are not built again.
SurfaceUncertainty propagated_uncertainty(const PointCloud& cloud, const Parameters& params, const std::vector<double>* w,
                                          const BSplineSurface& surface, const std::vector<double>& distances,
                                          const LeastSquaresFit* kept = nullptr);

// The device's fit (surface_from_device_fit) is a plain least-squares fit of every point of its
// scan, so the scan file's points give it a fit report: their orthogonal distances to it, the
// noise estimated from them, and its coefficients' covariance propagated to u(x, y) (each point's
// parameters over the device's rectangle). `device_points` and `device_rejected` are the device's
// own counts; unless they say that it fitted exactly the scan's points, no uncertainty is stated.
// Returns "" or why the uncertainty is not stated.
std::string add_scan_to_device_fit(FittedSurface& device_fit, const PointCloud& scan, uint32_t device_points,
                                   uint32_t device_rejected);

}  // namespace dg::host

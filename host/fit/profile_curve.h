// Planar profiles (x, z) as clamped cubic B-splines (Hlavova 2021): natural cubic interpolation,
// least-squares approximation, the control-polygon curve CAD programs draw, and the curve that
// passes at a prescribed distance (the probe's uncertainty) from every measured point.
#pragma once
#include <string>
#include <vector>

#include "host/geometry/point3.h"
#include "host/geometry/bspline_curve.h"
#include "host/geometry/distance_stats.h"

namespace dg::host {

// z = a x^3 + b x^2 + c x + d by least squares (Hlavova 2021, Table 3).
struct ProfileCubic {
  double a = 0, b = 0, c = 0, d = 0;
  double at(double x) const { return ((a * x + b) * x + c) * x + d; }
};

// Throws FitError (naming `name`) for fewer than 4 points, points not in one plane y = constant
// (within 1 um), or two successive points in one place.
void check_profile(const std::vector<Point3>& points, const std::string& name);

ProfileCubic fit_profile_cubic(const std::vector<Point3>& points);

// The C2 cubic through every point on chord-length parameters with zero second derivative at
// both ends (a natural spline), as a clamped cubic B-spline (n + 2 control points).
BSplineCurve interpolate_natural(const std::vector<Point3>& points);

struct ApproximationReport {
  int corrections = 0;          // parameter corrections taken
  double chord_rms_mm = 0;      // RMS distance on chord-length parameters, before correction
  double corrected_rms_mm = 0;  // after: the RMS of the foot-point (orthogonal) distances
  // The curve's standard uncertainty (k = 1) across itself at each point's foot, from the points'
  // scatter about it (more points than control points needed; empty otherwise, with the reason).
  std::vector<double> u_mm;
  double u_max_mm = 0, u_mean_mm = 0;
  std::string u_not_determined;
};

// The least-squares clamped cubic with `control_count` control points (uniform knots), its ends on
// the first and last point, starting from chord-length parameters and improved by parameter
// correction (each point's parameter moved to its foot point on the curve, then refitted) until
// the RMS distance stops falling.
BSplineCurve approximate_clamped(const std::vector<Point3>& points, int control_count,
                                 ApproximationReport* report = nullptr);

// The clamped cubic whose control polygon is the points themselves: what a CAD program draws for
// "curve from control points" (Hlavova's (2021) clamped cubic of Tables 2, 4 and 5).
BSplineCurve control_polygon_curve(const std::vector<Point3>& points);

struct CeCurve {
  BSplineCurve curve;
  ProfileCubic trend;               // the least-squares cubic that picks each offset's side
  std::vector<Point3> offset_points;  // the points the curve interpolates
};

// Hlavova 2021, section 3: interpolate, offset each point along that curve's normal by `distance_mm`
// to both sides, keep one side by the least-squares cubic, interpolate the kept points.
CeCurve curve_within_uncertainty(const std::vector<Point3>& points, double distance_mm);

// Distance from each point to the curve along the curve's normal (the closest point).
std::vector<double> curve_distances(const BSplineCurve& curve, const std::vector<Point3>& points);

}  // namespace dg::host

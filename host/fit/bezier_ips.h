// Bicubic Bezier patches by Hamdan's (2010) inverse progressive search (section 3): boundary curves from
// tangent-line intersections and a search along the tangents, then the four interior points.
#pragma once
#include <array>
#include <vector>

#include "host/scan/point_reader.h"
#include "host/geometry/bspline_surface.h"
#include "host/fit/parameterize.h"

namespace dg::host {

struct CubicBezierCurve {
  std::array<Point3, 4> p;  // control points, mm
  Point3 at(double t) const;
  Point3 derivative(double t) const;
  Point3 second_derivative(double t) const;
};

// The parameter of the curve point closest to q, by Newton's method from t0, within [0, 1].
double closest_parameter(const CubicBezierCurve& curve, const Point3& q, double t0);

// Hamdan 2010, eq. 13-16: where the tangent from a through b meets the tangent from c through d (in
// 3D: the midpoint of the lines' closest approach). False for parallel lines.
bool tangent_intersection(const Point3& a, const Point3& b, const Point3& c, const Point3& d, Point3& meet);

struct IpsCurve {
  CubicBezierCurve curve;
  Point3 meet;                    // P^c, the tangent intersection (or the fallback search end)
  bool tangents_meet = false;     // false: parallel or diverging tangents, searched over the chord
  double rms_mm = 0;              // eq. 11 with orthogonal distances
};

// The boundary curve of Hamdan 2010, section 3.2 for points ordered along it (at least 3): P1 and P4 are
// the end points, P2 and P3 lie on the end tangents and are found by a progressive search. Throws
// FitError for fewer than 3 points or coincident end points.
IpsCurve ips_curve(const std::vector<Point3>& points);

struct IpsSurface {
  BSplineSurface surface;            // degree 3 x 3, 4 x 4 control points, parameters [0, 1]^2
  std::array<IpsCurve, 4> boundary;  // v = 0 (first line), v = 1 (last line), u = 0, u = 1
  double rms_mm = 0;                 // over the points the interior search used
};

// The whole patch from scan lines (the cloud's `line`, at least 3 lines of at least 3 points).
// `params` are per-line parameters (chord length, say), which order the points of each line and start
// the closest-point searches. Throws FitError when the lines cannot frame a patch.
IpsSurface fit_bezier_ips(const PointCloud& cloud, const Parameters& params);

}  // namespace dg::host

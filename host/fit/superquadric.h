// Superquadric recovery (Koivunen and Bajcsy 1992, section 5.5): size, squareness, position and orientation of the
// whole part by Levenberg-Marquardt on the inside-outside function with the volume factor (eq. 10).
#pragma once
#include <string>
#include <vector>

#include "host/geometry/point3.h"
#include "host/geometry/bspline_surface.h"

namespace dg::host {

struct Superquadric {
  double a[3] = {1, 1, 1};   // half sizes along the object's x, y, z axes, mm
  double e1 = 1, e2 = 1;     // squareness in the latitude (z) and longitude (xy) planes
  Point3 center;             // mm
  double axes[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // rows: the object's x, y, z axes in the table's frame

  // The inside-outside function F = f^e1 of eq. 9 at a point in the table's frame: 1 on the
  // surface, below inside, above outside.
  double inside_outside(Point3 p) const;
  // The point of the surface at latitude eta in [-pi/2, pi/2] and longitude omega in [-pi, pi).
  Point3 surface_point(double eta, double omega) const;
};

enum class SuperquadricShape { kEllipsoid, kCylinder, kParallelepiped, kRotational, kOther };

// Standard uncertainties (k = 1) of the fitted parameters, from the scatter of the points about
// the fitted shape; computed false when the points do not determine them.
struct SuperquadricUncertainty {
  bool computed = false;
  double a_mm[3] = {0, 0, 0};
  double e1 = 0, e2 = 0;
  double center_mm[3] = {0, 0, 0};
};

struct SuperquadricFit {
  Superquadric model;
  SuperquadricUncertainty uncertainty;
  int iterations = 0;
  double objective = 0;           // eq. 10 at the solution
  double goodness = 0;            // eq. 10 divided by the number of points (Koivunen and Bajcsy 1992, Table 2's measure)
  double rms_radial_mm = 0;       // RMS of |p - c| * |1 - F^(-1/2)|: the distance along the ray from the centre
  SuperquadricShape shape = SuperquadricShape::kOther;
  bool rotationally_symmetric = false;  // e2 ~ 1 and a1 ~ a2: a surface of revolution about the z axis
  std::string description;        // "cylinder (rotationally symmetric about ...)", for people
};

struct SuperquadricOptions {
  int max_iterations = 200;
  double shape_tolerance = 0.2;   // Koivunen and Bajcsy's (1992) delta for the shape classes
  double size_tolerance = 0.05;   // |a1 - a2| / max(a1, a2) for rotational symmetry
};

// Throws FitError for fewer than 11 points, non-finite points, or points without volume (all in
// one plane or on one line): a superquadric needs extent in three directions.
SuperquadricFit fit_superquadric(const std::vector<Point3>& points, const SuperquadricOptions& options = {});

const char* shape_name(SuperquadricShape shape);

// Koivunen and Bajcsy 1992, section 6's check of a rotational symmetry: circles fitted by direct least squares to
// slices of the points across the assumed axis; the line through their centres is the axis, and
// their radii along it are the profile of the surface of revolution.
struct RevolutionSlice {
  double s_mm = 0;       // position along the axis from the superquadric's centre
  Point3 center;
  double radius_mm = 0;
  double rms_mm = 0;     // of the slice's points around its circle
  size_t points = 0;
};
struct RevolutionFit {
  Point3 axis_point, axis_direction;  // the refined axis (through the slice centres)
  std::vector<RevolutionSlice> slices;
  double rms_mm = 0;                  // all points around their slice's circle
};
// Slices with fewer than 8 points are skipped; throws FitError when fewer than 2 slices remain.
RevolutionFit fit_revolution(const std::vector<Point3>& points, const Superquadric& model, int slices = 10);

// The surface of revolution of a RevolutionFit (Koivunen and Bajcsy 1992, section 6's pin): the slice radii along
// the axis interpolated by a cubic, swept around the axis. Our surfaces are non-rational, so the
// circle is a periodic uniform cubic B-spline with `angular_controls` control points whose knot
// points lie on the circle; between them it departs from it by 4e-6 of the radius for 32 (measured
// in the tests), falling as the fourth power of the count. Returned clamped, u along the axis and v around it. Throws FitError for fewer
// than 2 slices.
BSplineSurface revolution_surface(const RevolutionFit& fit, int angular_controls = 32);

}  // namespace dg::host

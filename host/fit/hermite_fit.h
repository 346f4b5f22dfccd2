// Bicubic Hermite surfaces through a grid of points with normals (Li and Zhang 2013), returned as the
// equivalent B-spline (one Bezier patch per grid cell) so everything downstream takes it.
#pragma once
#include <vector>

#include "host/geometry/point3.h"
#include "host/scan/point_reader.h"
#include "host/geometry/bspline_surface.h"

namespace dg::host {

// Points in rows: point(row, col) = points[row * cols + col]. Along a row is u, across rows v.
struct HermiteGrid {
  int rows = 0, cols = 0;
  std::vector<Point3> points, normals;  // mm; normals of any non-zero length
};

struct HermiteResult {
  BSplineSurface surface;            // knots of multiplicity 3: one bicubic patch per cell
  std::vector<double> u, v;          // parameters of the grid's columns and rows (chord length, mm)
  double normal_residual_max = 0;    // largest |n . t| / |t| over all tangents: 0 = every constraint met
  bool closed_u = false;             // rows that end where they start, joined C2 there
  bool closed_v = false;             // columns likewise (Li and Zhang's (2013) cylinder and cone)
};

// The grid of a point cloud with normals: its scan lines (the `line` column, or lines found by
// segmentation) are the rows, each turned to run the way the first does (a serpentine scan).
// Throws FitError naming `name` when normals are missing or the lines differ in length.
HermiteGrid hermite_grid(const PointCloud& cloud, const std::string& name);

// Throws FitError for a grid smaller than 3 x 3, rows of different lengths, a normal of zero
// length, a non-finite value or two grid points in one place.
HermiteResult fit_hermite(const HermiteGrid& grid);

// One curve: tangents of the C2 cubic spline through `p` at parameters `t` whose end tangents are
// chosen so that n_k . d_k = 0 at every point they influence by at least 0.1 (in least squares when
// there are more such points than the six end-tangent components can satisfy) and, among those,
// nearest to the end derivatives of the cubic through the first and last four points, projected
// onto each end's tangent plane.
std::vector<Point3> constrained_tangents(const std::vector<Point3>& p, const std::vector<Point3>& n,
                                         const std::vector<double>& t);
// The derivatives of the closed C2 spline through `f` (f.front() and f.back() the same point) at
// parameters `t`: no ends, the last derivative equals the first.
std::vector<Point3> periodic_derivatives(const std::vector<Point3>& f, const std::vector<double>& t);
// The C2 spline's derivatives through values `f` at parameters `t` with both end derivatives given.
std::vector<Point3> spline_derivatives(const std::vector<Point3>& f, const std::vector<double>& t, Point3 first,
                                       Point3 last);

}  // namespace dg::host

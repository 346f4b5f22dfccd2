// A non-rational B-spline surface in millimetres: knots, control net, evaluation with derivatives.
#pragma once
#include <string>
#include <vector>

#include "host/geometry/point3.h"

namespace dg::host {

struct BSplineSurface {
  int degree_u = 3, degree_v = 3;
  int count_u = 0, count_v = 0;          // control points in each direction
  std::vector<double> knots_u, knots_v;  // count + degree + 1 each, non-decreasing
  std::vector<Point3> control;           // control[i * count_v + j], mm

  Point3& at(int i, int j) { return control[static_cast<size_t>(i) * count_v + j]; }
  const Point3& at(int i, int j) const { return control[static_cast<size_t>(i) * count_v + j]; }
  double u_min() const { return knots_u[degree_u]; }
  double u_max() const { return knots_u[count_u]; }
  double v_min() const { return knots_v[degree_v]; }
  double v_max() const { return knots_v[count_v]; }

  Point3 evaluate(double u, double v) const;
  // The point and its first partial derivatives.
  void evaluate(double u, double v, Point3& s, Point3& su, Point3& sv) const;
};

// A clamped knot vector (end knots repeated degree + 1 times) with uniform interior knots on [0, 1].
std::vector<double> clamped_uniform_knots(int count, int degree);
// The Greville abscissa of control point i: the mean of its degree interior knots. A B-spline whose
// control values are a linear function of these abscissae is that linear function.
double greville(const std::vector<double>& knots, int degree, int i);
// The distinct knot values within [lo, hi], ascending: the ends of the non-empty spans.
std::vector<double> distinct_knots(const std::vector<double>& knots, double lo, double hi);
// Checks counts, degrees, knot order and lengths; the message says what is wrong.
bool is_valid(const BSplineSurface& s, std::string* why);

}  // namespace dg::host

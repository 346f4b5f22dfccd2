// A low-order polynomial z(x, y) fitted by least squares to a handful of neighbouring points.
#pragma once
#include <cmath>
#include <cstddef>
#include <vector>

#include "host/geometry/point3.h"

namespace dg::host {

namespace polynomial_terms {

// The first N terms (3, 6 or 10) at (dx, dy).
template <int N>
inline void terms(double dx, double dy, double* t) {
  t[0] = 1, t[1] = dx, t[2] = dy;
  if constexpr (N >= 6) t[3] = dx * dx, t[4] = dx * dy, t[5] = dy * dy;
  if constexpr (N == 10) t[6] = dx * dx * dx, t[7] = dx * dx * dy, t[8] = dx * dy * dy, t[9] = dy * dy * dy;
}

// The polynomial of N terms with coefficients c at (dx, dy), summed in the terms' order.
template <int N>
inline double value(const double* c, double dx, double dy) {
  double t[N];
  terms<N>(dx, dy, t);
  double z = 0;
#pragma GCC unroll 10
  for (int k = 0; k < N; ++k) z += c[k] * t[k];
  return z;
}

// The polynomial of `order` (1, 2 or 3) at (dx, dy).
inline double value_of_order(int order, const double* c, double dx, double dy) {
  switch (order) {
    case 1: return value<3>(c, dx, dy);
    case 2: return value<6>(c, dx, dy);
    default: return value<10>(c, dx, dy);
  }
}

}  // namespace polynomial_terms

// z = c0 + c1 dx + c2 dy (+ c3 dx^2 + c4 dx dy + c5 dy^2 (+ the four cubic terms)), with dx, dy measured from `centre` and
// scaled by the neighbourhood's extent so the normal equations stay well conditioned in any unit.
struct LocalPolynomial {
  int order = 1;  // 1: plane (3 terms), 2: quadratic (6 terms), 3: cubic (10 terms)
  Point3 centre;
  double scale_x = 1, scale_y = 1;
  double c[10] = {};
  // [(X^T X)^-1]_00: the variance of the value at the centre in units of the noise variance (1/n
  // for a centre among the points, more where the centre lies off to one side of them).
  double centre_gain = 0;
  // A tilted model (fit_tilted_polynomial): dx, dy and the value are offsets from `centre` along
  // the frame's axes `axis_u`, `axis_v` and `normal`, not along x, y and z.
  bool tilted = false;
  double axis_u[3] = {1, 0, 0}, axis_v[3] = {0, 1, 0}, normal[3] = {0, 0, 1};

  int terms() const { return order == 1 ? 3 : order == 2 ? 6 : 10; }
  // The model surface's height z above (x, y); for an upright model at the centre it is c[0].
  // Inline for an upright model: the LTS filter asks it of every point of a window at each of its
  // steps, and in a profile the call and the switch on the order were the iteration's hottest lines.
  double at(double x, double y) const {
    if (tilted) return tilted_at(x, y);
    return polynomial_terms::value_of_order(order, c, (x - centre.x) / scale_x, (y - centre.y) / scale_y);
  }
  // The same, checked: false where a tilted model's surface has no height above (x, y) that Newton's
  // steps reach (the vertical there misses the surface, or meets it where it turns over), and `z`
  // is then the last step's value, no height of the model. An upright model always has one.
  bool height(double x, double y, double& z) const;
  // at() for an upright model; for a tilted one its height(), or HUGE_VAL where it has none, so
  // that a point there is missed by any bound rather than judged by a number the model lacks.
  double height_or_huge(double x, double y) const {
    if (!tilted) return at(x, y);
    double z = 0;
    return height(x, y, z) ? z : HUGE_VAL;
  }

 private:
  double tilted_at(double x, double y) const;
};

// Fits the model to points[indices]; false when they do not determine it (too few, or collinear in XY).
bool fit_local_polynomial(const std::vector<Point3>& points, const std::vector<size_t>& indices, const Point3& centre,
                          int order, LocalPolynomial& out);

// The same in a frame tilted to `normal` (a unit vector with a positive z): the polynomial gives
// the offset along the normal over the plane through `centre` across it. On a steep flank a
// quadratic in x and y misses the surface by far more than one in its tangent plane (a 5 x 5 window
// at 1 mm on a 12.7 mm sphere, 11 mm from its axis: 0.11 mm against 0.008 mm on average, heights
// as z), so a model that is to tell a 20 sigma outlier from the shape there is fitted so.
bool fit_tilted_polynomial(const std::vector<Point3>& points, const std::vector<size_t>& indices, const Point3& centre,
                           const double (&normal)[3], int order, LocalPolynomial& out);

}  // namespace dg::host

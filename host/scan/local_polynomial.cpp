// Local plane, quadratic and cubic fits through the shared packed LDL^T solver.
#include "host/scan/local_polynomial.h"

#include <algorithm>
#include <cmath>

#include "common/fit/dense_ldlt.h"

namespace dg::host {

namespace {

int polynomial_terms(int order, double dx, double dy, double* t) {
  t[0] = 1, t[1] = dx, t[2] = dy;
  if (order == 1) return 3;
  t[3] = dx * dx, t[4] = dx * dy, t[5] = dy * dy;
  if (order == 2) return 6;
  t[6] = dx * dx * dx, t[7] = dx * dx * dy, t[8] = dx * dy * dy, t[9] = dy * dy * dy;
  return 10;
}

}  // namespace

double LocalPolynomial::at(double x, double y) const {
  double t[10];
  const int n = polynomial_terms(order, (x - centre.x) / scale_x, (y - centre.y) / scale_y, t);
  double z = 0;
  for (int k = 0; k < n; ++k) z += c[k] * t[k];
  return z;
}

bool fit_local_polynomial(const std::vector<Point3>& points, const std::vector<size_t>& indices, const Point3& centre,
                          int order, LocalPolynomial& out) {
  out.order = order;
  out.centre = centre;
  out.scale_x = out.scale_y = 0;
  for (size_t j : indices) {
    out.scale_x = std::max(out.scale_x, std::fabs(points[j].x - centre.x));
    out.scale_y = std::max(out.scale_y, std::fabs(points[j].y - centre.y));
  }
  if (!(out.scale_x > 0) || !(out.scale_y > 0)) return false;
  const int n = out.terms();
  if (indices.size() < static_cast<size_t>(n)) return false;
  double a[fit::packed_size(10)] = {}, inverse_d[10];
  for (double& value : out.c) value = 0;
  for (size_t j : indices) {
    double t[10];
    polynomial_terms(order, (points[j].x - centre.x) / out.scale_x, (points[j].y - centre.y) / out.scale_y, t);
    for (int r = 0; r < n; ++r) {
      for (int k = 0; k <= r; ++k) a[fit::packed_index(r, k)] += t[r] * t[k];
      out.c[r] += t[r] * points[j].z;
    }
  }
  if (fit::ldlt_factor(a, n, inverse_d, 1e-10) != Status::kOk) return false;
  fit::ldlt_solve(a, inverse_d, n, out.c);
  double first_column[10] = {1};
  fit::ldlt_solve(a, inverse_d, n, first_column);
  out.centre_gain = first_column[0];
  return true;
}

}  // namespace dg::host

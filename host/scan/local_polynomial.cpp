// Local plane, quadratic and cubic fits through the shared packed LDL^T solver.
#include "host/scan/local_polynomial.h"

#include <algorithm>
#include <cmath>

#include "common/fit/dense_ldlt.h"

namespace dg::host {

namespace {

// The first N terms (3, 6 or 10) at (dx, dy).
template <int N>
void terms(double dx, double dy, double* t) {
  t[0] = 1, t[1] = dx, t[2] = dy;
  if constexpr (N >= 6) t[3] = dx * dx, t[4] = dx * dy, t[5] = dy * dy;
  if constexpr (N == 10) t[6] = dx * dx * dx, t[7] = dx * dx * dy, t[8] = dx * dy * dy, t[9] = dy * dy * dy;
}

// The polynomial of N terms with coefficients c at (dx, dy), summed in the terms' order.
template <int N>
double value(const double* c, double dx, double dy) {
  double t[N];
  terms<N>(dx, dy, t);
  double z = 0;
#pragma GCC unroll 10
  for (int k = 0; k < N; ++k) z += c[k] * t[k];
  return z;
}

// The points' terms into the normal equations (packed lower triangle) and the right-hand side, N
// terms a point. N is fixed at compile time so the loops unroll: with it a variable the loop took
// 460 instructions a point for a cubic, most of the LTS filter's time. The same sums in the same
// order either way.
template <int N>
void add_points(const std::vector<Point3>& points, const std::vector<size_t>& indices, const LocalPolynomial& model,
                double* a, double* c) {
  for (size_t j : indices) {
    double t[N];
    terms<N>((points[j].x - model.centre.x) / model.scale_x, (points[j].y - model.centre.y) / model.scale_y, t);
#pragma GCC unroll 10
    for (int r = 0; r < N; ++r) {
#pragma GCC unroll 10
      for (int k = 0; k <= r; ++k) a[fit::packed_index(r, k)] += t[r] * t[k];
      c[r] += t[r] * points[j].z;
    }
  }
}

// The shared LDL^T solver inlined whole with its size a constant: about a tenth fewer instructions
// than the generic call, which took some 3,800 to factor a cubic's 10 x 10 (the triangular loops
// stay loops at -O2). The same operations in the same order.
template <int N>
__attribute__((flatten)) bool solve_fixed(double* a, double* c, double* centre_gain) {
  double inverse_d[N];
  if (fit::ldlt_factor(a, N, inverse_d, 1e-10) != Status::kOk) return false;
  fit::ldlt_solve(a, inverse_d, N, c);
  double first_column[N] = {1};
  fit::ldlt_solve(a, inverse_d, N, first_column);
  *centre_gain = first_column[0];
  return true;
}

}  // namespace

double LocalPolynomial::at(double x, double y) const {
  const double dx = (x - centre.x) / scale_x, dy = (y - centre.y) / scale_y;
  switch (order) {
    case 1: return value<3>(c, dx, dy);
    case 2: return value<6>(c, dx, dy);
    default: return value<10>(c, dx, dy);
  }
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
  double a[fit::packed_size(10)] = {};
  for (double& value : out.c) value = 0;
  switch (n) {
    case 3: add_points<3>(points, indices, out, a, out.c); break;
    case 6: add_points<6>(points, indices, out, a, out.c); break;
    default: add_points<10>(points, indices, out, a, out.c); break;
  }
  switch (n) {
    case 3: return solve_fixed<3>(a, out.c, &out.centre_gain);
    case 6: return solve_fixed<6>(a, out.c, &out.centre_gain);
    default: return solve_fixed<10>(a, out.c, &out.centre_gain);
  }
}

}  // namespace dg::host

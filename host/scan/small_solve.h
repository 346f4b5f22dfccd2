// Dense solves of the few-unknown least-squares systems a calibration fits (spheres, axes, tilt).
#pragma once
#include <cmath>
#include <utility>

namespace dg::host {

// Solves the leading n x n block of a x = b (n <= N) by Gaussian elimination with partial
// pivoting, overwriting a and b; false when it is singular (a pivot below 1e-12).
template <int N>
bool solve_small(int n, double (&a)[N][N], double (&b)[N], double (&x)[N]) {
  for (int col = 0; col < n; ++col) {
    int pivot = col;
    for (int r = col + 1; r < n; ++r) {
      if (std::fabs(a[r][col]) > std::fabs(a[pivot][col])) pivot = r;
    }
    if (!(std::fabs(a[pivot][col]) > 1e-12)) return false;
    std::swap(a[col], a[pivot]);
    std::swap(b[col], b[pivot]);
    for (int r = col + 1; r < n; ++r) {
      const double f = a[r][col] / a[col][col];
      for (int c = col; c < n; ++c) a[r][c] -= f * a[col][c];
      b[r] -= f * b[col];
    }
  }
  for (int r = n - 1; r >= 0; --r) {
    double s = b[r];
    for (int c = r + 1; c < n; ++c) s -= a[r][c] * x[c];
    x[r] = s / a[r][r];
  }
  return true;
}

// The diagonal of a^-1 (a symmetric positive definite, n <= N), for the variances of a
// least-squares fit's parameters; false when a is singular. `a` is left as it was.
template <int N>
bool inverse_diagonal(int n, const double (&a)[N][N], double (&diagonal)[N]) {
  for (int i = 0; i < n; ++i) {
    double copy[N][N], unit[N] = {}, column[N] = {};
    for (int r = 0; r < N; ++r)
      for (int c = 0; c < N; ++c) copy[r][c] = a[r][c];
    unit[i] = 1;
    if (!solve_small(n, copy, unit, column)) return false;
    diagonal[i] = column[i];
  }
  return true;
}

}  // namespace dg::host

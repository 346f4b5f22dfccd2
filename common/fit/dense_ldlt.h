// A small dense LDL^T solver on packed symmetric storage, for any scalar type (device and host).
#pragma once

#include "common/fit/scalar.h"
#include "common/status.h"

namespace dg::fit {

// Index of element (row, col), col <= row, in a packed lower triangle stored row by row.
constexpr int packed_index(int row, int col) { return row * (row + 1) / 2 + col; }
constexpr int packed_size(int n) { return n * (n + 1) / 2; }

// Factors the symmetric matrix in `a` (packed lower triangle, n x n) in place into L (unit lower,
// below the diagonal) and D (on the diagonal). LDL^T needs no square roots, so it runs in fixed
// point. A pivot that falls to `relative_floor` of its original diagonal or below means the matrix is
// (numerically) singular: the data do not determine every unknown, and the caller must say so.
// `Inverse` holds 1/d per column: one division per column, multiplications elsewhere.
template <typename T>
Status ldlt_factor(T* a, int n, T* inverse_d, T relative_floor) {
  for (int j = 0; j < n; ++j) {
    T d = a[packed_index(j, j)];
    const T original = d;
    for (int k = 0; k < j; ++k) {
      const T l = a[packed_index(j, k)];
      d = d - l * l * a[packed_index(k, k)];
    }
    if (ScalarTraits<T>::is_zero_or_negative(d) || ScalarTraits<T>::is_zero_or_negative(original) ||
        !(original * relative_floor < d)) {
      return Status::kInvalidArgument;
    }
    a[packed_index(j, j)] = d;
    inverse_d[j] = one<T>() / d;
    for (int i = j + 1; i < n; ++i) {
      T sum = a[packed_index(i, j)];
      for (int k = 0; k < j; ++k) {
        sum = sum - a[packed_index(i, k)] * a[packed_index(j, k)] * a[packed_index(k, k)];
      }
      a[packed_index(i, j)] = sum * inverse_d[j];
    }
  }
  return Status::kOk;
}

// Solves L D L^T x = b in place in `b` after ldlt_factor.
template <typename T>
void ldlt_solve(const T* factored, const T* inverse_d, int n, T* b) {
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < i; ++k) b[i] = b[i] - factored[packed_index(i, k)] * b[k];
  }
  for (int i = 0; i < n; ++i) b[i] = b[i] * inverse_d[i];
  for (int i = n - 1; i >= 0; --i) {
    for (int k = i + 1; k < n; ++k) b[i] = b[i] - factored[packed_index(k, i)] * b[k];
  }
}

}  // namespace dg::fit

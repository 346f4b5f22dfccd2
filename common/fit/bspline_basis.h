// B-spline basis functions and their derivatives on a knot vector (Koivunen and Bajcsy 1992, eq. 4-5), any scalar type.
#pragma once

#include "common/fit/bernstein.h"

namespace dg::fit {

// The knot span i with knots[i] <= u < knots[i+1], for a clamped knot vector of
// `control_count + degree + 1` knots; u at the right end belongs to the last non-empty span.
template <typename T>
constexpr int find_span(int control_count, int degree, T u, const T* knots) {
  const int last = control_count - 1;
  if (!(u < knots[last + 1])) return last;
  if (u < knots[degree + 1]) return degree;
  int lo = degree, hi = last + 1;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (u < knots[mid]) hi = mid; else lo = mid;
  }
  return lo;
}

// The degree+1 non-zero basis values N_{span-degree..span}(u), and their first derivatives when
// `d1` is not null. The Cox-de Boor recurrence (Koivunen and Bajcsy 1992, eq. 5) arranged as a triangle so that each
// value is computed once; the 0/0 = 0 convention appears as skipped zero-length spans.
template <typename T>
constexpr void bspline_basis(int span, int degree, T u, const T* knots, T* n, T* d1 = nullptr) {
  T left[kMaxDegree + 1] = {}, right[kMaxDegree + 1] = {};
  T lower[kMaxDegree + 1] = {};  // degree-1 values, for the derivative
  n[0] = one<T>();
  for (int j = 1; j <= degree; ++j) {
    left[j] = u - knots[span + 1 - j];
    right[j] = knots[span + j] - u;
    if (j == degree && d1 != nullptr) {
      for (int r = 0; r < j; ++r) lower[r] = n[r];
    }
    T saved = zero<T>();
    for (int r = 0; r < j; ++r) {
      const T width = right[r + 1] + left[j - r];
      const T temp = ScalarTraits<T>::is_zero_or_negative(width) ? zero<T>() : n[r] / width;
      n[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    n[j] = saved;
  }
  if (d1 == nullptr) return;
  // N'_{i,p} = p (N_{i,p-1} / (t_{i+p} - t_i) - N_{i+1,p-1} / (t_{i+p+1} - t_{i+1})).
  if (degree == 0) {
    d1[0] = zero<T>();
    return;
  }
  const T p = ScalarTraits<T>::from_int(degree);
  // term[r] = N_{span-degree+r+1, degree-1} / (t_{span+r+1} - t_{span-degree+r+1}); each of the
  // degree widths is divided by once and serves two derivatives.
  T term[kMaxDegree + 1] = {};
  for (int r = 0; r < degree; ++r) {
    const T width = knots[span + r + 1] - knots[span - degree + r + 1];
    term[r] = ScalarTraits<T>::is_zero_or_negative(width) ? zero<T>() : lower[r] / width;
  }
  for (int r = 0; r <= degree; ++r) {
    const T before = r > 0 ? term[r - 1] : zero<T>();
    const T after = r < degree ? term[r] : zero<T>();
    d1[r] = p * (before - after);
  }
}

}  // namespace dg::fit

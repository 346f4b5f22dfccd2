// Bernstein polynomials of any degree (the Bezier basis), evaluated for any scalar type.
#pragma once

#include "common/fit/scalar.h"

namespace dg::fit {

constexpr int kMaxDegree = 7;

// out[0..degree] = B_{i,degree}(u) by de Casteljau's triangle, which only adds products of
// u and 1-u (all in [0, 1]) and so never leaves the range of a Q-format basis type. For degree 3
// this is Hamdan 2010, eq. 6: U1 = (1-u)^3, U2 = 3u(1-u)^2, U3 = 3u^2(1-u), U4 = u^3.
template <typename T>
constexpr void bernstein(int degree, T u, T* out) {
  const T s = one<T>() - u;
  out[0] = one<T>();
  for (int j = 1; j <= degree; ++j) {
    T saved = zero<T>();
    for (int k = 0; k < j; ++k) {
      const T temp = out[k];
      out[k] = saved + s * temp;
      saved = u * temp;
    }
    out[j] = saved;
  }
}

// Derivative of a Bernstein sum: d/du sum P_i B_{i,n} = n sum (P_{i+1} - P_i) B_{i,n-1}.
// Returns dB_{i,n}/du in out[0..degree].
template <typename T>
constexpr void bernstein_derivative(int degree, T u, T* out) {
  T lower[kMaxDegree + 1] = {};
  if (degree == 0) {
    out[0] = zero<T>();
    return;
  }
  bernstein(degree - 1, u, lower);
  const T n = ScalarTraits<T>::from_int(degree);
  for (int i = 0; i <= degree; ++i) {
    const T left = i > 0 ? lower[i - 1] : zero<T>();
    const T right = i < degree ? lower[i] : zero<T>();
    out[i] = n * (left - right);
  }
}

}  // namespace dg::fit

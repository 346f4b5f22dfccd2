// What the fitting core needs from a scalar type: constants and ratios, for double, float and fixed point.
#pragma once
#include <stdint.h>

#include "common/fixed/q.h"

namespace dg::fit {

template <typename T>
struct ScalarTraits;

template <>
struct ScalarTraits<double> {
  static constexpr double from_int(int32_t n) { return n; }
  static constexpr double from_ratio(int64_t num, int64_t den) {
    return static_cast<double>(num) / static_cast<double>(den);
  }
  static constexpr bool is_zero_or_negative(double v) { return !(v > 0.0); }
};

template <>
struct ScalarTraits<float> {
  static constexpr float from_int(int32_t n) { return static_cast<float>(n); }
  static constexpr float from_ratio(int64_t num, int64_t den) {
    return static_cast<float>(static_cast<double>(num) / static_cast<double>(den));
  }
  static constexpr bool is_zero_or_negative(float v) { return !(v > 0.0f); }
};

template <int F>
struct ScalarTraits<fx::Q<F>> {
  static constexpr fx::Q<F> from_int(int32_t n) { return fx::Q<F>::from_int(n); }
  static constexpr fx::Q<F> from_ratio(int64_t num, int64_t den) { return fx::Q<F>::from_ratio(num, den); }
  static constexpr bool is_zero_or_negative(fx::Q<F> v) { return v.raw <= 0; }
};

template <>
struct ScalarTraits<fx::Q32x32> {
  static constexpr fx::Q32x32 from_int(int32_t n) { return fx::Q32x32::from_int(n); }
  static constexpr fx::Q32x32 from_ratio(int64_t num, int64_t den) {
    return fx::Q32x32::from_raw(num) / fx::Q32x32::from_raw(den);  // (num << 32) / den
  }
  static constexpr bool is_zero_or_negative(fx::Q32x32 v) { return v.raw <= 0; }
};

template <typename T>
constexpr T one() {
  return ScalarTraits<T>::from_int(1);
}
template <typename T>
constexpr T zero() {
  return ScalarTraits<T>::from_int(0);
}

}  // namespace dg::fit

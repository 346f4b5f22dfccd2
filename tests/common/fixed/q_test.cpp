// Q-format arithmetic against double: rounding, 128-bit products, long division, saturation.
#include "common/fixed/q.h"

#include <CppUTest/TestHarness.h>

#include <cmath>

#include <random>

using dg::fx::Q;
using dg::fx::Q32x32;

namespace {
double to_double(Q32x32 q) { return static_cast<double>(q.raw) / 4294967296.0; }
Q32x32 from_double(double v) { return Q32x32::from_raw(static_cast<int64_t>(std::llround(v * 4294967296.0))); }
}  // namespace

TEST_GROUP(FixedPoint){};

TEST(FixedPoint, Q30ProductRoundsToNearest) {
  const auto half = Q<30>::from_ratio(1, 2);
  const auto third = Q<30>::from_ratio(1, 3);
  const auto p = half * third;
  CHECK(std::fabs(p.raw / 1073741824.0 - 1.0 / 6.0) <= 1.0 / 1073741824.0);
  LONGS_EQUAL(Q<15>::from_ratio(1, 6).raw, (half * third).to<15>().raw);
}

TEST(FixedPoint, Q32x32MultipliesAndDividesLikeDoubleAcrossTheRange) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> mantissa(-0.5, 0.5);
  std::uniform_int_distribution<int> exponent(-12, 14);  // products stay inside +-2^31
  for (int i = 0; i < 20000; ++i) {
    const double a = mantissa(rng) * std::ldexp(1.0, exponent(rng));
    const double b = mantissa(rng) * std::ldexp(1.0, exponent(rng));
    const Q32x32 qa = from_double(a), qb = from_double(b);
    const double exact_product = to_double(qa) * to_double(qb);
    // The reference product in double carries its own rounding of 2^-52 relative.
    DOUBLES_EQUAL(exact_product, to_double(qa * qb), 0.51 / 4294967296.0 + 4e-16 * std::fabs(exact_product));
    if (std::fabs(to_double(qb)) > 1e-3 && std::fabs(to_double(qa) / to_double(qb)) < 1e9) {
      const double exact_quotient = to_double(qa) / to_double(qb);
      DOUBLES_EQUAL(exact_quotient, to_double(qa / qb), 0.51 / 4294967296.0 + 1e-15 * std::fabs(exact_quotient));
    }
  }
}

TEST(FixedPoint, Q32x32SaturatesInsteadOfWrapping) {
  const Q32x32 big = Q32x32::from_int(100000);
  CHECK((big * big).is_saturated());
  CHECK((-big * big).raw < 0);
  CHECK((Q32x32::from_int(1) / Q32x32::from_raw(0)).is_saturated());
  CHECK((big / Q32x32::from_raw(1)).is_saturated());
  CHECK(!(Q32x32::from_int(3) / Q32x32::from_int(7)).is_saturated());
}

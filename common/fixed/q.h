// Q-format fixed-point numbers: Q<F> (32-bit, F fraction bits) and Q32x32 (64-bit, 32 fraction bits).
#pragma once
#include <stdint.h>

namespace dg::fx {

// Rounds a 64-bit value shifted right by `shift` to nearest (ties away from zero).
constexpr int64_t round_shift(int64_t value, int shift) {
  const int64_t half = int64_t{1} << (shift - 1);
  return value >= 0 ? (value + half) >> shift : -((-value + half) >> shift);
}

// A 32-bit Q-format value with F fraction bits. Products use one 32x32->64 multiply, which is a
// single instruction on a Cortex-M3/M4 (SMULL); used for basis values, which lie in [0, 1].
template <int F>
struct Q {
  static_assert(F > 0 && F < 31, "fraction bits");
  static constexpr int kFractionBits = F;
  int32_t raw = 0;

  static constexpr Q from_raw(int32_t r) {
    Q q;
    q.raw = r;
    return q;
  }
  static constexpr Q from_int(int32_t n) { return from_raw(n * (int32_t{1} << F)); }
  // num/den, rounded; den > 0.
  static constexpr Q from_ratio(int64_t num, int64_t den) {
    const int64_t scaled = num * (int64_t{1} << F);
    return from_raw(static_cast<int32_t>(scaled >= 0 ? (scaled + den / 2) / den : -((-scaled + den / 2) / den)));
  }
  // Changes the number of fraction bits, rounding.
  template <int G>
  constexpr Q<G> to() const {
    if constexpr (G >= F) {
      return Q<G>::from_raw(raw * (int32_t{1} << (G - F)));
    } else {
      return Q<G>::from_raw(static_cast<int32_t>(round_shift(raw, F - G)));
    }
  }

  friend constexpr Q operator+(Q a, Q b) { return from_raw(a.raw + b.raw); }
  friend constexpr Q operator-(Q a, Q b) { return from_raw(a.raw - b.raw); }
  friend constexpr Q operator-(Q a) { return from_raw(-a.raw); }
  friend constexpr Q operator*(Q a, Q b) {
    return from_raw(static_cast<int32_t>(round_shift(int64_t{a.raw} * b.raw, F)));
  }
  friend constexpr Q operator*(Q a, int32_t n) { return from_raw(a.raw * n); }
  friend constexpr bool operator==(Q a, Q b) { return a.raw == b.raw; }
  friend constexpr bool operator<(Q a, Q b) { return a.raw < b.raw; }
  Q& operator+=(Q b) { raw += b.raw; return *this; }
  Q& operator-=(Q b) { raw -= b.raw; return *this; }
};

// Unsigned 64x64 -> 128 multiply from 32-bit halves (portable: no __int128 on 32-bit ARM).
struct U128 {
  uint64_t hi, lo;
};
constexpr U128 mul_u64(uint64_t a, uint64_t b) {
  const uint64_t a_lo = a & 0xffffffffu, a_hi = a >> 32, b_lo = b & 0xffffffffu, b_hi = b >> 32;
  const uint64_t ll = a_lo * b_lo, lh = a_lo * b_hi, hl = a_hi * b_lo, hh = a_hi * b_hi;
  const uint64_t mid = (ll >> 32) + (lh & 0xffffffffu) + (hl & 0xffffffffu);
  return U128{hh + (lh >> 32) + (hl >> 32) + (mid >> 32), (mid << 32) | (ll & 0xffffffffu)};
}

// A 64-bit Q32.32 value: range +-2^31, resolution 2^-32. The device's dense solver runs in it.
// Arithmetic saturates to +-INT64_MAX instead of wrapping; `is_saturated()` tells a result that did.
class Q32x32 {
 public:
  static constexpr int kFractionBits = 32;
  int64_t raw = 0;

  static constexpr Q32x32 from_raw(int64_t r) {
    Q32x32 q;
    q.raw = r;
    return q;
  }
  static constexpr Q32x32 from_int(int32_t n) { return from_raw(int64_t{n} * (int64_t{1} << 32)); }

  friend constexpr Q32x32 operator+(Q32x32 a, Q32x32 b) { return from_raw(a.raw + b.raw); }
  friend constexpr Q32x32 operator-(Q32x32 a, Q32x32 b) { return from_raw(a.raw - b.raw); }
  friend constexpr Q32x32 operator-(Q32x32 a) { return from_raw(-a.raw); }
  friend constexpr bool operator<(Q32x32 a, Q32x32 b) { return a.raw < b.raw; }
  friend constexpr bool operator==(Q32x32 a, Q32x32 b) { return a.raw == b.raw; }
  Q32x32& operator+=(Q32x32 b) { raw += b.raw; return *this; }
  Q32x32& operator-=(Q32x32 b) { raw -= b.raw; return *this; }
  constexpr bool is_saturated() const { return raw == INT64_MAX || raw == -INT64_MAX; }

  friend constexpr Q32x32 operator*(Q32x32 a, Q32x32 b) {
    const bool negative = (a.raw < 0) != (b.raw < 0);
    const U128 p = mul_u64(magnitude(a.raw), magnitude(b.raw));
    // (p >> 32) rounded; saturate when it does not fit in 63 bits.
    const uint64_t lo = p.lo + (uint64_t{1} << 31);
    const uint64_t hi = p.hi + (lo < p.lo ? 1 : 0);
    if (hi >> 31) return saturate(negative);
    const uint64_t shifted = (hi << 32) | (lo >> 32);
    return from_raw(negative ? -static_cast<int64_t>(shifted) : static_cast<int64_t>(shifted));
  }
  // Long division of (a << 32) by b: only the solver's few pivots are divided, so speed is secondary.
  friend constexpr Q32x32 operator/(Q32x32 a, Q32x32 b) {
    if (b.raw == 0) return saturate(a.raw < 0);
    const bool negative = (a.raw < 0) != (b.raw < 0);
    const uint64_t d = magnitude(b.raw);
    const uint64_t n = magnitude(a.raw);
    uint64_t rem = 0, quotient = 0;
    // Dividend bits: n's 64 bits followed by 32 zero bits.
    for (int bit = 95; bit >= 0; --bit) {
      const uint64_t next = bit >= 32 ? (n >> (bit - 32)) & 1u : 0u;
      if (rem >> 63) return saturate(negative);
      rem = (rem << 1) | next;
      if (quotient >> 62) return saturate(negative);
      quotient <<= 1;
      if (rem >= d) {
        rem -= d;
        quotient |= 1u;
      }
    }
    if (rem >= d - rem) ++quotient;  // round to nearest
    if (quotient >> 63) return saturate(negative);
    return from_raw(negative ? -static_cast<int64_t>(quotient) : static_cast<int64_t>(quotient));
  }

 private:
  static constexpr uint64_t magnitude(int64_t v) {
    return v < 0 ? uint64_t{0} - static_cast<uint64_t>(v) : static_cast<uint64_t>(v);
  }
  static constexpr Q32x32 saturate(bool negative) { return from_raw(negative ? -INT64_MAX : INT64_MAX); }
};

}  // namespace dg::fx

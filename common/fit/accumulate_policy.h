// How each scalar type multiplies and accumulates in the streaming normal equations.
#pragma once
#include <math.h>
#include <stdint.h>

#include "common/fixed/q.h"

namespace dg::fit {

// Maps an offset along an axis, 0..range (integer nm), to a parameter in [0, 1]. Fixed point uses a
// precomputed reciprocal so that a point costs a multiply and a shift, not a 64-bit division.
struct UnitScale {
  int64_t range = 1;
  int64_t multiplier = 0;  // floor(2^(30 + shift) / range), < 2^31
  int shift = 0;
  static UnitScale for_range(int64_t range) {
    UnitScale scale;
    scale.range = range > 0 ? range : 1;
    while (scale.shift < 32 && (int64_t{1} << (30 + scale.shift + 1)) / scale.range < (int64_t{1} << 31)) {
      ++scale.shift;
    }
    scale.multiplier = (int64_t{1} << (30 + scale.shift)) / scale.range;
    return scale;
  }
};

// Floating point: basis, value and sums in one type; the solver runs in the same type.
template <typename T>
struct FloatingPolicy {
  using Unit = T;  // a parameter in [0, 1] and the one-dimensional basis values
  using Basis = T;
  using Value = T;  // a coordinate in mm
  using Accum = T;
  using Solve = T;
  // The fixed-point policy's limits, kept here too so that a host fit in double accepts exactly the
  // points the device's fit accepts and the two can be compared.
  static constexpr int32_t kMaxValueNm = (int32_t{1} << 27) - 1;
  static constexpr uint32_t kMaxPoints = uint32_t{1} << 20;
  using Weighted = T;  // a height times a basis value
  static Unit unit_product(Unit a, Unit b) { return a * b; }
  static Accum product(Basis a, Basis b) { return a * b; }
  static Weighted weigh_value(Basis a, Value v) { return a * v; }
  static Accum moment_value(Basis a, Weighted w) { return a * w; }
  // Sums times small integers and divided by them, when block moments become normal equations.
  static Accum weighted(Accum sum, int32_t n) { return sum * static_cast<T>(n); }
  static Accum divided(Accum sum, int32_t d) { return sum / static_cast<T>(d); }
  static Accum rhs_from_moments(Accum sum) { return sum; }
  // A sum kept in a solver entry's storage until it is converted in place (same type here).
  static Solve hold(Accum sum) { return sum; }
  static Accum held(Solve entry) { return entry; }
  // Entries are scaled by powers of two (see solve_normal_sums), which is exact in any type.
  static int diagonal_exponent(Accum sum, uint32_t count) {
    int e = 0;
    frexp(static_cast<double>(sum / static_cast<T>(count)), &e);
    return (2 - e) / 2;  // mean * 4^k in [0.25, 1)
  }
  static Solve matrix_entry(Accum sum, uint32_t count, int exponent) {
    return static_cast<T>(ldexp(static_cast<double>(sum / static_cast<T>(count)), exponent));
  }
  static Solve rhs_entry(Accum sum, uint32_t count, int exponent) { return matrix_entry(sum, count, exponent); }
  static Value to_value(Solve x, int exponent) { return static_cast<T>(ldexp(static_cast<double>(x), exponent)); }
  static Value value_from_nm(int32_t nm) { return static_cast<T>(nm) * static_cast<T>(1e-6); }
  static Unit unit(int64_t offset, const UnitScale& scale) {
    return static_cast<T>(static_cast<double>(offset) / static_cast<double>(scale.range));
  }
  // s = u * spans split into the span index (clamped to the last span) and the local t in [0, 1].
  static void split(Unit u, int spans, int& span, Unit& t) {
    const T s = u * static_cast<T>(spans);
    span = static_cast<int>(s);
    if (span > spans - 1) span = spans - 1;
    if (span < 0) span = 0;
    t = s - static_cast<T>(span);
  }
};

// Fixed point for a device without an FPU: basis values in Q1.30 (32-bit), coordinates as integer
// nanometres, sums in 64 bits. A product of two basis values is rounded to Q28 (kProductBits): one
// 32x32->64 multiply (UMULL on a Cortex-M3/M4), its high word and the bit below it. The basis is not
// rounded to Q1.F first: with 2^-16 basis values a 120 mm height carried 2 um into every product, and the fit of a tilted
// part or a coarse grid, whose points repeat the same basis values line after line, drifted up to
// 5 um from the same fit in double. A height times two basis values is taken in two steps, each one
// 32x32-bit multiply: the height times the v value to 1/16 nm (it fits 32 bits), then times the u
// value to 2^-(F-3) nm. With F = 15 a moment of basis values grows by at most 2^28 per point and a
// height moment by at most 2^12 |z_nm|, so with 2^20 points of |z| < 2^27 nm (134 mm) the block
// moments (at most 2^48 and 2^59) can be multiplied by the conversion's numerators (at most 2^12
// and 8, height_field_fit.h) and still fit 63 bits; `kMaxValueNm` and `kMaxPoints` state that
// limit and the sums refuse points beyond it.
template <int F>
struct FixedPolicy {
  using Unit = fx::Q<30>;  // parameters and one-dimensional basis values, in [0, 1]
  using Basis = fx::Q<30>;
  using Value = int32_t;  // nm
  using Accum = int64_t;
  using Solve = fx::Q32x32;  // mm
  static constexpr int32_t kMaxValueNm = (int32_t{1} << 27) - 1;
  static constexpr uint32_t kMaxPoints = uint32_t{1} << (62 - F - 27);
  // Rounded half up (basis values are never negative, so the product is taken unsigned).
  static constexpr int kProductBits = 28;
  [[gnu::always_inline]] static Accum product(Basis a, Basis b) {
    const uint64_t p = uint64_t{static_cast<uint32_t>(a.raw)} * static_cast<uint32_t>(b.raw);
    return static_cast<Accum>(static_cast<uint32_t>(p >> 32) + (static_cast<uint32_t>(p) >> 31));
  }
  // The product of two parameters or basis values in [0, 1], rounded half up: inline, where
  // Q's own product takes the sign into account.
  [[gnu::always_inline]] static Unit unit_product(Unit a, Unit b) {
    return Unit::from_raw(static_cast<int32_t>((int64_t{a.raw} * b.raw + (int64_t{1} << 29)) >> 30));
  }
  using Weighted = int32_t;  // a height times a basis value: nm with kWeightedBits fraction bits
  static constexpr int kWeightedBits = 4;
  static constexpr int kMomentValueBits = F - 3;
  static Weighted weigh_value(Basis a, Value v) {
    constexpr int shift = 30 - kWeightedBits;
    return static_cast<Weighted>((int64_t{a.raw} * v + (int64_t{1} << (shift - 1))) >> shift);
  }
  static Accum moment_value(Basis a, Weighted w) {
    constexpr int shift = 30 + kWeightedBits - kMomentValueBits;
    return (int64_t{a.raw} * w + (int64_t{1} << (shift - 1))) >> shift;
  }
  static Accum weighted(Accum sum, int32_t n) { return sum * n; }
  // Rounded to nearest, ties away from zero.
  static Accum divided(Accum sum, int32_t d) { return sum >= 0 ? (sum + d / 2) / d : -((-sum + d / 2) / d); }
  // A height moment's 2^-(F-3) nm to the right-hand side's 2^-F nm.
  static Accum rhs_from_moments(Accum sum) { return sum * (int64_t{1} << (F - kMomentValueBits)); }
  // A 64-bit sum kept in a Q32.32 entry's storage until it is converted in place.
  static Solve hold(Accum sum) { return Solve::from_raw(sum); }
  static Accum held(Solve entry) { return entry.raw; }
  // The k that brings the mean diagonal product into [1/4, 1) when multiplied by 4^k.
  static int diagonal_exponent(Accum sum, uint32_t count) {
    const int64_t mean = sum / static_cast<int64_t>(count);  // Q(kProductBits), at most 1
    int k = 0;
    while (k < 15 && mean > 0 && (mean << (2 * k)) < (int64_t{1} << (kProductBits - 2))) ++k;
    return k;
  }
  // 2^exponent * sum / count as Q32.32. With the diagonal scaled into [1/4, 1), every scaled entry is
  // at most 1 in magnitude (Cauchy-Schwarz), so the shifted sum stays below count * 2^32.
  static Solve matrix_entry(Accum sum, uint32_t count, int exponent) {
    return Solve::from_raw(sum * (int64_t{1} << (32 - kProductBits + exponent)) / count);
  }
  // 2^exponent times the mean in nm (F fraction bits), converted to mm in Q32.32. The scaled mean is
  // bounded by the largest |value| (Cauchy-Schwarz again), so the shifts cannot overflow.
  static Solve rhs_entry(Accum sum, uint32_t count, int exponent) {
    const int64_t mean_nm_qf = sum / static_cast<int64_t>(count) * (int64_t{1} << exponent);
    return Solve::from_raw(mean_nm_qf * (int64_t{1} << (32 - F)) / 1000000);
  }
  // 2^exponent * x mm in Q32.32 to nm: raw * 10^6 / 2^32 = raw * 15625 / 2^26; saturates at the
  // int32 limits.
  static Value to_value(Solve x_mm, int exponent) {
    const int64_t limit = int64_t{1} << (43 - exponent);
    if (x_mm.raw >= limit) return INT32_MAX;
    if (x_mm.raw <= -limit) return -INT32_MAX;
    const int64_t nm = fx::round_shift(x_mm.raw * 15625, 26 - exponent);
    return nm > INT32_MAX ? INT32_MAX : nm < -INT32_MAX ? -INT32_MAX : static_cast<Value>(nm);
  }
  static Value value_from_nm(int32_t nm) { return nm; }
  // offset / range in Q1.30 for 0 <= offset <= range < 2^31 nm; the reciprocal's relative error is
  // below 2^-30, so the parameter is within one unit in the last place.
  static Unit unit(int64_t offset, const UnitScale& scale) {
    const int64_t u = (offset * scale.multiplier + (int64_t{1} << (scale.shift - 1))) >> scale.shift;
    return Unit::from_raw(static_cast<int32_t>(u > (int64_t{1} << 30) ? (int64_t{1} << 30) : u));
  }
  static void split(Unit u, int spans, int& span, Unit& t) {
    const int64_t s = int64_t{u.raw} * spans;
    span = static_cast<int>(s >> 30);
    if (span > spans - 1) span = spans - 1;
    if (span < 0) span = 0;
    t = Unit::from_raw(static_cast<int32_t>(s - (int64_t{span} << 30)));
  }
};

}  // namespace dg::fit

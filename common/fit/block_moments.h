// Streaming sums of measured heights over a rectangle cut into span blocks: the moments every bicubic fit's normal equations are made from.
#pragma once
#include <stdint.h>

#include "common/fit/accumulate_policy.h"
#include "common/status.h"

namespace dg::fit {

// The rectangle of the table a fit covers, in nm; u runs along x, v along y.
struct FitRegion {
  int32_t x_min_nm = 0, x_max_nm = 0, y_min_nm = 0, y_max_nm = 0;
  bool valid() const { return x_max_nm > x_min_nm && y_max_nm > y_min_nm; }
};

// The cubic Bernstein values B3_0..3(t) and the sextic B6_0..6(t) of a local parameter t in [0, 1].
// B6 comes from products of the cubic ones (B6_{r+s} C(3,r) C(3,s) = C(6,r+s) B3_r B3_s), so a
// point costs seven more products. Every value is a product, never a difference: fixed-point
// products take them for unsigned, and B6_3 taken as one minus the others had come out a few
// units below zero near the ends of a span.
template <typename Policy, typename Unit>
[[gnu::always_inline]] inline void cubic_and_sextic_bernstein(Unit t, Unit* b3, Unit* b6) {
  const Unit s = one<Unit>() - t;
  const Unit t2 = Policy::unit_product(t, t), s2 = Policy::unit_product(s, s);
  const Unit t3 = Policy::unit_product(t2, t), s3 = Policy::unit_product(s2, s);
  b3[0] = s3;
  b3[1] = Policy::unit_product(t, s2) * 3;
  b3[2] = Policy::unit_product(t2, s) * 3;
  b3[3] = t3;
  b6[0] = Policy::unit_product(s3, s3);
  b6[1] = Policy::unit_product(b3[0], b3[1]) * 2;
  b6[2] = Policy::unit_product(b3[0], b3[2]) * 5;
  b6[4] = Policy::unit_product(b3[1], b3[3]) * 5;
  b6[5] = Policy::unit_product(b3[2], b3[3]) * 2;
  b6[6] = Policy::unit_product(t3, t3);
  b6[3] = Policy::unit_product(s3, t3) * 20;
}

// One block's sums (see BlockMoments).
template <typename Policy>
struct MomentBlock {
  typename Policy::Accum sextic[7][7];  // sum of B6_a(t_u) B6_b(t_v) (Policy::product units)
  typename Policy::Accum height[4][4];  // sum of B3_r(t_u) B3_s(t_v) (z - first z) (Policy::moment_value units)
};

// Sums over the points of a rectangle cut into Spans x Spans equal blocks. Within a block any
// cubic basis is a set of cubic polynomials, so the products of two basis functions are sextics and
// a height times a basis function a cubic: the block's 49 sums of B6_a(t_u) B6_b(t_v) and 16 sums
// of B3_r(t_u) B3_s(t_v) z hold every sum of the normal equations of a Bezier patch or a cubic
// B-spline net whose spans are made of whole blocks (height_field_fit.h converts them). A point
// costs the same whatever the scan's order or the length of its lines. Heights are taken
// relative to the first point's, which keeps fixed-point sums small and loses nothing (it is
// added back).
template <typename Policy, int Spans>
class BlockMoments {
 public:
  using Unit = typename Policy::Unit;
  using Accum = typename Policy::Accum;
  static constexpr int kSpans = Spans;
  static_assert(Spans >= 1, "at least one block");

  using Block = MomentBlock<Policy>;

  void begin(const FitRegion& region) {
    region_ = region;
    scale_u_ = UnitScale::for_range(int64_t{region.x_max_nm} - region.x_min_nm);
    scale_v_ = UnitScale::for_range(int64_t{region.y_max_nm} - region.y_min_nm);
    for (auto& row : blocks_) {
      for (Block& block : row) block = Block{};
    }
    count_ = rejected_ = 0;
    has_reference_ = false;
  }

  // One measured point. Points outside the region, or too far from the first height for the sums,
  // are counted as rejected and do not change the sums.
  Status add(int32_t x_nm, int32_t y_nm, int32_t z_nm) {
    if (!region_.valid()) return Status::kNotReady;
    if (x_nm < region_.x_min_nm || x_nm > region_.x_max_nm || y_nm < region_.y_min_nm ||
        y_nm > region_.y_max_nm) {
      ++rejected_;
      return Status::kInvalidArgument;
    }
    if (!has_reference_) {
      reference_z_nm_ = z_nm;
      has_reference_ = true;
    }
    const int64_t dz = int64_t{z_nm} - reference_z_nm_;
    if (dz > Policy::kMaxValueNm || dz < -Policy::kMaxValueNm || count_ >= Policy::kMaxPoints) {
      ++rejected_;
      return Status::kOverflow;
    }
    int span_u = 0, span_v = 0;
    Unit t_u, t_v;
    Policy::split(Policy::unit(int64_t{x_nm} - region_.x_min_nm, scale_u_), Spans, span_u, t_u);
    Policy::split(Policy::unit(int64_t{y_nm} - region_.y_min_nm, scale_v_), Spans, span_v, t_v);
    Unit cubic_u[4], cubic_v[4], sextic_u[7], sextic_v[7];
    cubic_and_sextic_bernstein<Policy>(t_u, cubic_u, sextic_u);
    cubic_and_sextic_bernstein<Policy>(t_v, cubic_v, sextic_v);
    Block& block = blocks_[span_u][span_v];
    // Unrolled: the loop's own counting cost a fifth of each product.
#pragma GCC unroll 7
    for (int a = 0; a < 7; ++a) {
      Accum* row = block.sextic[a];
      const Unit b_a = sextic_u[a];
#pragma GCC unroll 7
      for (int b = 0; b < 7; ++b) row[b] += Policy::product(b_a, sextic_v[b]);
    }
    const typename Policy::Value value = Policy::value_from_nm(static_cast<int32_t>(dz));
#pragma GCC unroll 4
    for (int s = 0; s < 4; ++s) {
      const typename Policy::Value weighted = Policy::weigh_value(cubic_v[s], value);
#pragma GCC unroll 4
      for (int r = 0; r < 4; ++r) block.height[r][s] += Policy::moment_value(cubic_u[r], weighted);
    }
    ++count_;
    return Status::kOk;
  }

  uint32_t count() const { return count_; }
  uint32_t rejected() const { return rejected_; }
  const FitRegion& region() const { return region_; }
  int32_t reference_z_nm() const { return reference_z_nm_; }
  const Block& block(int span_u, int span_v) const { return blocks_[span_u][span_v]; }

 private:
  FitRegion region_;
  UnitScale scale_u_, scale_v_;
  Block blocks_[Spans][Spans] = {};
  uint32_t count_ = 0, rejected_ = 0;
  int32_t reference_z_nm_ = 0;
  bool has_reference_ = false;
};

}  // namespace dg::fit

// Streaming height-field fits over a rectangle of the table: a Bezier patch and a uniform B-spline net.
#pragma once
#include <stdint.h>

#include <type_traits>

#include "common/fit/accumulate_policy.h"
#include "common/fit/bernstein.h"
#include "common/fit/dense_ldlt.h"
#include "common/fit/normal_equations.h"

namespace dg::fit {

// The rectangle of the table a fit covers, in nm; u runs along x, v along y.
struct FitRegion {
  int32_t x_min_nm = 0, x_max_nm = 0, y_min_nm = 0, y_max_nm = 0;
  bool valid() const { return x_max_nm > x_min_nm && y_max_nm > y_min_nm; }
};

// Cubic uniform B-spline basis on a span, t in [0, 1] (the four blending functions of a span).
template <typename T>
void uniform_cubic_basis(T t, T* out) {
  const T one_t = one<T>();
  const T sixth = ScalarTraits<T>::from_ratio(1, 6);
  const T s = one_t - t;
  const T t2 = t * t, t3 = t2 * t;
  out[0] = s * s * s * sixth;
  out[3] = t3 * sixth;
  // (3t^3 - 6t^2 + 4) / 6 written as t^3/2 - t^2 + 2/3 so that no term leaves [-2, 2] (Q1.30);
  // the fourth follows from the four summing to one.
  out[1] = t3 * ScalarTraits<T>::from_ratio(1, 2) - t2 + ScalarTraits<T>::from_ratio(2, 3);
  out[2] = one_t - out[0] - out[1] - out[3];
}

// z(u, v) = sum P_ij B_i(u) B_j(v) fitted while points arrive. Heights are taken relative to the
// first point's, which keeps fixed-point sums small and loses nothing (it is added back).
// Kind supplies the basis: BezierBasis (one patch) or UniformCubicBasis<K> (a K x K net).
template <typename Policy, typename Kind>
class HeightFieldFit {
 public:
  using Basis = typename Policy::Basis;
  using Unit = typename Policy::Unit;
  using Value = typename Policy::Value;
  using Solve = typename Policy::Solve;
  using Accum = typename Policy::Accum;
  static constexpr int kSide = Kind::kSide;
  // Basis values enter the products at the parameters' precision (accumulate_policy.h says why).
  static_assert(std::is_same<Basis, Unit>::value, "a policy's basis values are its parameters' type");
  static constexpr int kUnknowns = kSide * kSide;

  void begin(const FitRegion& region) {
    region_ = region;
    scale_u_ = UnitScale::for_range(int64_t{region.x_max_nm} - region.x_min_nm);
    scale_v_ = UnitScale::for_range(int64_t{region.y_max_nm} - region.y_min_nm);
    equations_.clear();
    clear_line();
    rejected_ = 0;
    has_reference_ = false;
  }

  // One measured point. Points outside the region, or too far from the first height for the sums,
  // are counted as rejected and do not change the fit.
  //
  // Points that share y (a scan line along x) share their v basis values, so the product of two
  // tensor basis values factors: c_(i,j) c_(k,l) = (bu_i bu_k)(bv_j bv_l). A point adds only the
  // ten along-line products bu_i bu_k and four bu_i z; the line's sums are multiplied by the v
  // products once, when y changes or before a solve. That is what keeps a point within about a
  // thousand instructions on a Cortex-M4 instead of 136 products for the patch's 16 unknowns.
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
    if (dz > Policy::kMaxValueNm || dz < -Policy::kMaxValueNm || count() >= Policy::kMaxPoints) {
      ++rejected_;
      return Status::kOverflow;
    }
    if (!line_open_ || y_nm != line_y_nm_) {
      flush_line();
      const Unit v = Policy::unit(int64_t{y_nm} - region_.y_min_nm, scale_v_);
      Kind::template basis<Policy>(v, line_bv_, line_span_v_);
      line_y_nm_ = y_nm;
      line_open_ = true;
    }
    const Unit u = Policy::unit(int64_t{x_nm} - region_.x_min_nm, scale_u_);
    Basis b[4];
    int span_u = 0;
    Kind::template basis<Policy>(u, b, span_u);
    const Value value = Policy::value_from_nm(static_cast<int32_t>(dz));
    for (int i = 0; i < 4; ++i) {
      Accum* row = &line_matrix_[packed_index(span_u + i, span_u)];
      for (int k = 0; k <= i; ++k) row[k] += Policy::product(b[i], b[k]);
      line_rhs_[span_u + i] += Policy::product_value(b[i], value);
    }
    ++line_count_;
    return Status::kOk;
  }

  uint32_t count() const { return equations_.count() + line_count_; }
  uint32_t rejected() const { return rejected_; }
  const FitRegion& region() const { return region_; }

  using Workspace = typename NormalEquations<Policy, kUnknowns, 1>::Workspace;

  // Control heights P[i][j] (i along x, j along y), in the policy's value unit (nm or mm).
  // kNotReady: fewer points than unknowns; kInvalidArgument: the points leave some control point
  // undetermined (for example all on one line).
  Status solve(Value (&heights)[kSide][kSide], Workspace& work) {
    flush_line();
    if (equations_.count() < static_cast<uint32_t>(kUnknowns)) return Status::kNotReady;
    Value x[1][kUnknowns];
    const Status status = equations_.solve(x, work, ScalarTraits<Solve>::from_ratio(1, 1000000));
    if (status != Status::kOk) return status;
    for (int i = 0; i < kSide; ++i) {
      for (int j = 0; j < kSide; ++j) heights[i][j] = x[0][i * kSide + j] + Policy::value_from_nm(reference_z_nm_);
    }
    return Status::kOk;
  }

 private:
  void clear_line() {
    for (auto& sum : line_matrix_) sum = Accum{};
    for (auto& sum : line_rhs_) sum = Accum{};
    line_count_ = 0;
    line_open_ = false;
  }

  // Adds the open line's sums times its v products to the normal equations. Unknown (i, j) is
  // i * kSide + j, so row i > k gives row (i, j) > (k, l) for every j, l; on i == k only j >= l
  // is a distinct entry of the symmetric matrix.
  void flush_line() {
    if (line_count_ == 0) {
      line_open_ = false;
      return;
    }
    // The v products, full (bvv[j][l] == bvv[l][j]), so an entry's four l are one contiguous run.
    Unit bvv[4][4];
    for (int j = 0; j < 4; ++j) {
      for (int l = 0; l <= j; ++l) bvv[j][l] = bvv[l][j] = line_bv_[j] * line_bv_[l];
    }
    // Row (i, j) of the packed matrix holds columns (k, l) for k < i at k kSide + span + l, four
    // in a row; for k == i only l <= j.
    for (int i = 0; i < kSide; ++i) {
      for (int j = 0; j < 4; ++j) {
        const int row = i * kSide + line_span_v_ + j;
        Accum* row_sums = &equations_.matrix_sum(row, 0);
        const Unit* v = bvv[j];
        for (int k = 0; k < i; ++k) {
          const Accum sum = line_matrix_[packed_index(i, k)];
          if (sum == Accum{}) continue;  // outside the band of a net
          Accum* out = row_sums + k * kSide + line_span_v_;
          for (int l = 0; l < 4; ++l) out[l] += Policy::scale(sum, v[l]);
        }
        const Accum diagonal = line_matrix_[packed_index(i, i)];
        if (diagonal != Accum{}) {
          Accum* out = row_sums + i * kSide + line_span_v_;
          for (int l = 0; l <= j; ++l) out[l] += Policy::scale(diagonal, v[l]);
        }
        equations_.rhs_sum(0, row) += Policy::scale(line_rhs_[i], line_bv_[j]);
      }
    }
    equations_.add_count(line_count_);
    clear_line();
  }

  FitRegion region_;
  UnitScale scale_u_, scale_v_;
  NormalEquations<Policy, kUnknowns, 1> equations_;
  uint32_t rejected_ = 0;
  int32_t reference_z_nm_ = 0;
  bool has_reference_ = false;
  // The scan line being summed (see add()).
  Accum line_matrix_[packed_size(kSide)] = {};
  Accum line_rhs_[kSide] = {};
  Unit line_bv_[4] = {};
  int line_span_v_ = 0;
  int32_t line_y_nm_ = 0;
  uint32_t line_count_ = 0;
  bool line_open_ = false;
};

// One bicubic Bezier patch over the region.
struct BezierBasis {
  static constexpr int kSide = 4;
  template <typename Policy>
  static void basis(typename Policy::Unit u, typename Policy::Unit* out, int& first) {
    bernstein(3, u, out);
    first = 0;
  }
};

// A K x K uniform cubic B-spline net (knots (i - 3) / (K - 3), i = 0..K+3) over the region.
template <int K>
struct UniformCubicBasis {
  static_assert(K >= 4, "a cubic net needs at least 4 x 4 control points");
  static constexpr int kSide = K;
  template <typename Policy>
  static void basis(typename Policy::Unit u, typename Policy::Unit* out, int& first) {
    typename Policy::Unit t;
    Policy::split(u, K - 3, first, t);
    uniform_cubic_basis(t, out);
  }
};

}  // namespace dg::fit

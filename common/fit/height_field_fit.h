// Height-field fits over a rectangle of the table, a Bezier patch and a uniform B-spline net, solved from streamed block moments.
#pragma once
#include <stdint.h>

#include "common/fit/accumulate_policy.h"
#include "common/fit/bernstein.h"
#include "common/fit/block_moments.h"
#include "common/fit/dense_ldlt.h"
#include "common/fit/normal_equations.h"

namespace dg::fit {

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

// One bicubic Bezier patch over the region: one span whose four functions are the cubic Bernstein
// polynomials themselves.
struct BezierBasis {
  static constexpr int kSide = 4;
  static constexpr int kSpans = 1;
  static constexpr int kPieceDenominator = 1;
  static constexpr int8_t kPiece[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  static constexpr int first(int /*span*/) { return 0; }
  template <typename Policy>
  static void basis(typename Policy::Unit u, typename Policy::Unit* out, int& first) {
    bernstein(3, u, out);
    first = 0;
  }
};

// A K x K uniform cubic B-spline net (knots (i - 3) / (K - 3), i = 0..K+3) over the region. On a
// span the four functions are, in Bernstein form, (1,0,0,0)/6, (4,4,2,1)/6, (1,2,4,4)/6 and
// (0,0,0,1)/6 (the uniform cubic B-spline's pieces, converted from their power form).
template <int K>
struct UniformCubicBasis {
  static_assert(K >= 4, "a cubic net needs at least 4 x 4 control points");
  static constexpr int kSide = K;
  static constexpr int kSpans = K - 3;
  static constexpr int kPieceDenominator = 6;
  static constexpr int8_t kPiece[4][4] = {{1, 0, 0, 0}, {4, 4, 2, 1}, {1, 2, 4, 4}, {0, 0, 0, 1}};
  static constexpr int first(int span) { return span; }
  template <typename Policy>
  static void basis(typename Policy::Unit u, typename Policy::Unit* out, int& first) {
    typename Policy::Unit t;
    Policy::split(u, K - 3, first, t);
    uniform_cubic_basis(t, out);
  }
};

// A kind's four functions on one moment block, and their pairwise products, as integer
// numerators over one denominator each: exact, so that converting moments loses nothing but one
// rounding per sum.
struct BlockCoefficients {
  int32_t piece[4][4] = {};  // B3 coefficients of local function i on the block, / piece_denominator
  int32_t piece_denominator = 1;
  int32_t product[10][7] = {};  // B6 coefficients of functions i * k, pair i (i + 1) / 2 + k, k <= i
  int32_t product_denominator = 1;
};

constexpr int pair_index(int i, int k) { return i * (i + 1) / 2 + k; }

// The kind's functions on the c-th of d equal parts of one of its spans. The restriction of a
// cubic to [a, b] has the Bernstein coefficients of its blossom at (a, a, a), (a, a, b), (a, b, b),
// (b, b, b); with a = c / d and b = (c + 1) / d the blossom of B3_q is an integer over d^3. A product
// B3_r B3_s is C(3,r) C(3,s) / C(6,r+s) B6_{r+s}; 60 is a multiple of every C(6,m).
template <typename Kind>
constexpr BlockCoefficients block_coefficients(int c, int d) {
  constexpr int64_t kBinomial3[4] = {1, 3, 3, 1};
  constexpr int64_t kBinomial6[7] = {1, 6, 15, 20, 15, 6, 1};
  int64_t restricted[4][4] = {};  // [q][r]: B3_q on the part, over d^3
  for (int q = 0; q < 4; ++q) {
    for (int r = 0; r < 4; ++r) {
      int64_t p[4] = {0, 0, 0, 0};
      p[q] = 1;
      for (int level = 0; level < 3; ++level) {
        const int64_t x = level < 3 - r ? c : c + 1;
        for (int k = 0; k + level < 3; ++k) p[k] = (d - x) * p[k] + x * p[k + 1];
      }
      restricted[q][r] = p[0];
    }
  }
  BlockCoefficients out;
  out.piece_denominator = Kind::kPieceDenominator * d * d * d;
  for (int i = 0; i < 4; ++i) {
    for (int r = 0; r < 4; ++r) {
      int64_t sum = 0;
      for (int q = 0; q < 4; ++q) sum += Kind::kPiece[i][q] * restricted[q][r];
      out.piece[i][r] = static_cast<int32_t>(sum);
    }
  }
  out.product_denominator = out.piece_denominator * out.piece_denominator * 60;
  for (int i = 0; i < 4; ++i) {
    for (int k = 0; k <= i; ++k) {
      for (int r = 0; r < 4; ++r) {
        for (int s = 0; s < 4; ++s) {
          out.product[pair_index(i, k)][r + s] += static_cast<int32_t>(
              out.piece[i][r] * out.piece[k][s] * kBinomial3[r] * kBinomial3[s] * (60 / kBinomial6[r + s]));
        }
      }
    }
  }
  return out;
}

// The coefficients of every part of a kind's span when the moments cut it into D parts.
template <typename Kind, int D>
struct BlockCoefficientTable {
  BlockCoefficients part[D];
  constexpr BlockCoefficientTable() : part() {
    for (int c = 0; c < D; ++c) part[c] = block_coefficients<Kind>(c, D);
  }
};

template <typename Policy, typename Kind>
using HeightFieldWorkspace = NormalWorkspace<Policy, Kind::kSide * Kind::kSide>;

// Adds one block's moments to the normal equations of `Kind`, whose unknown (i, j) (i along x) is
// i * kSide + j. A product of functions i, k along u and j, l along v sums
// sum_a sum_b U_ik,a V_jl,b sextic[a][b]: first over b for each of the ten (j, l), then over a.
template <typename Policy, typename Kind>
void add_block(const MomentBlock<Policy>& block, const BlockCoefficients& along_u,
               const BlockCoefficients& along_v, int first_u, int first_v, HeightFieldWorkspace<Policy, Kind>& work) {
  using Accum = typename Policy::Accum;
  constexpr int kSide = Kind::kSide;
  // One pair (j, l) at a time, so that a solve on a device keeps 7 sums on its stack, not 70.
  for (int j = 0; j < 4; ++j) {
    for (int l = 0; l <= j; ++l) {
      const int32_t* v = along_v.product[pair_index(j, l)];
      Accum over_v[7];
      for (int a = 0; a < 7; ++a) {
        Accum sum{};
        for (int b = 0; b < 7; ++b) {
          if (v[b] != 0) sum += Policy::weighted(block.sextic[a][b], v[b]);
        }
        over_v[a] = Policy::divided(sum, along_v.product_denominator);
      }
      for (int i = 0; i < 4; ++i) {
        for (int k = 0; k <= i; ++k) {
          const int32_t* u = along_u.product[pair_index(i, k)];
          Accum sum{};
          for (int a = 0; a < 7; ++a) {
            if (u[a] != 0) sum += Policy::weighted(over_v[a], u[a]);
          }
          const Accum entry = Policy::divided(sum, along_u.product_denominator);
          const int row_i = (first_u + i) * kSide + first_v, row_k = (first_u + k) * kSide + first_v;
          // Entry ((i, j), (k, l)); for i > k also ((i, l), (k, j)), the same product. For i == k
          // only the lower triangle (j >= l) is an entry of the packed symmetric matrix.
          work.add_matrix(row_i + j, row_k + l, entry);
          if (i > k && j != l) work.add_matrix(row_i + l, row_k + j, entry);
        }
      }
    }
  }
  Accum height_over_v[4][4];  // [r][j]
  for (int r = 0; r < 4; ++r) {
    for (int j = 0; j < 4; ++j) {
      Accum sum{};
      for (int s = 0; s < 4; ++s) {
        if (along_v.piece[j][s] != 0) sum += Policy::weighted(block.height[r][s], along_v.piece[j][s]);
      }
      height_over_v[r][j] = Policy::divided(sum, along_v.piece_denominator);
    }
  }
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      Accum sum{};
      for (int r = 0; r < 4; ++r) {
        if (along_u.piece[i][r] != 0) sum += Policy::weighted(height_over_v[r][j], along_u.piece[i][r]);
      }
      work.add_rhs((first_u + i) * kSide + first_v + j, Policy::rhs_from_moments(Policy::divided(sum, along_u.piece_denominator)));
    }
  }
}

// Control heights P[i][j] (i along x, j along y) of `Kind` fitted to the moments, in the policy's
// value unit (nm or mm). Moments cut into more blocks than the kind has spans serve too, as long
// as each span is made of whole blocks: a device keeps one set of sums for its Bezier patch and its
// net. kNotReady: fewer points than unknowns; kInvalidArgument: the points leave some control
// point undetermined (for example all on one line).
template <typename Kind, typename Policy, int Spans>
Status solve_height_field(const BlockMoments<Policy, Spans>& moments,
                          typename Policy::Value (&heights)[Kind::kSide][Kind::kSide],
                          HeightFieldWorkspace<Policy, Kind>& work) {
  static_assert(Spans % Kind::kSpans == 0, "each of the kind's spans is made of whole blocks");
  constexpr int kSide = Kind::kSide;
  constexpr int kParts = Spans / Kind::kSpans;
  static constexpr BlockCoefficientTable<Kind, kParts> kTable;
  if (moments.count() < static_cast<uint32_t>(kSide * kSide)) return Status::kNotReady;
  work.clear();
  for (int su = 0; su < Spans; ++su) {
    for (int sv = 0; sv < Spans; ++sv) {
      add_block<Policy, Kind>(moments.block(su, sv), kTable.part[su % kParts], kTable.part[sv % kParts], Kind::first(su / kParts),
                              Kind::first(sv / kParts), work);
    }
  }
  typename Policy::Value x[kSide * kSide];
  const Status status =
      solve_normal_sums<Policy, kSide * kSide>(work, moments.count(), x, ScalarTraits<typename Policy::Solve>::from_ratio(1, 1000000));
  if (status != Status::kOk) return status;
  for (int i = 0; i < kSide; ++i) {
    for (int j = 0; j < kSide; ++j) heights[i][j] = x[i * kSide + j] + Policy::value_from_nm(moments.reference_z_nm());
  }
  return Status::kOk;
}

// One fit streamed on its own: the moments cut as the kind's spans, and its solve.
template <typename Policy, typename Kind>
class HeightFieldFit {
 public:
  using Value = typename Policy::Value;
  using Workspace = HeightFieldWorkspace<Policy, Kind>;
  static constexpr int kSide = Kind::kSide;

  void begin(const FitRegion& region) { moments_.begin(region); }
  // See BlockMoments::add.
  Status add(int32_t x_nm, int32_t y_nm, int32_t z_nm) { return moments_.add(x_nm, y_nm, z_nm); }
  uint32_t count() const { return moments_.count(); }
  uint32_t rejected() const { return moments_.rejected(); }
  const FitRegion& region() const { return moments_.region(); }
  Status solve(Value (&heights)[kSide][kSide], Workspace& work) const {
    return solve_height_field<Kind>(moments_, heights, work);
  }

 private:
  BlockMoments<Policy, Kind::kSpans> moments_;
};

}  // namespace dg::fit

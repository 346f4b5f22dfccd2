// Streaming least-squares normal equations of fixed size: one point at a time, constant memory.
#pragma once
#include <stdint.h>

#include "common/fit/dense_ldlt.h"

namespace dg::fit {

// Accumulates C^T C and C^T z (Koivunen and Bajcsy 1992, eq. 8, [B] = [C^T C]^-1 C^T [S]) for N unknowns and R
// right-hand sides without storing the points: each point adds the outer product of its non-zero
// basis values. Memory is N(N+1)/2 + R*N sums whatever the number of points.
template <typename Policy, int N, int R = 1>
class NormalEquations {
 public:
  using Basis = typename Policy::Basis;
  using Value = typename Policy::Value;
  using Accum = typename Policy::Accum;
  using Solve = typename Policy::Solve;
  static constexpr int kUnknowns = N;
  static constexpr int kRhs = R;

  void clear() {
    for (auto& s : matrix_) s = Accum{};
    for (auto& row : rhs_) for (auto& s : row) s = Accum{};
    count_ = 0;
  }

  // One point: `count` basis values `c` for the unknowns `index` (ascending), and its R values.
  void add(const int* index, const Basis* c, int count, const Value* value) {
    for (int k = 0; k < count; ++k) {
      Accum* row = &matrix_[packed_index(index[k], 0)];
      const Basis ck = c[k];
      for (int l = 0; l <= k; ++l) row[index[l]] += Policy::product(ck, c[l]);
      for (int r = 0; r < R; ++r) rhs_[r][index[k]] += Policy::product_value(ck, value[r]);
    }
    ++count_;
  }

  uint32_t count() const { return count_; }

  // Direct access for callers that sum blocks of the products themselves (HeightFieldFit sums a
  // scan line's along-line products and adds them here once per line). Row i >= column j.
  Accum& matrix_sum(int i, int j) { return matrix_[packed_index(i, j)]; }
  Accum& rhs_sum(int r, int i) { return rhs_[r][i]; }
  void add_count(uint32_t points) { count_ += points; }

  // Memory for a solve, kept apart from the sums so that a device can share it between fits.
  struct Workspace {
    Solve factor[packed_size(N)];
    Solve inverse_d[N];
    Solve y[N];
    int exponent[N];
  };

  // Solves for the unknowns, which come back as Value (nm or mm) in x[r][i]. The equations are first
  // scaled symmetrically by powers of two so that every diagonal entry lies in [1/4, 1): exact in any
  // type, it evens out the magnitudes that fixed point must hold (an outer control point of a net
  // has a diagonal far below the others) and leaves the solution unchanged.
  Status solve(Value (&x)[R][N], Workspace& work, Solve relative_floor) const {
    if (count_ == 0) return Status::kNotReady;
    Solve* factor = work.factor;
    int* exponent = work.exponent;
    for (int i = 0; i < N; ++i) exponent[i] = Policy::diagonal_exponent(matrix_[packed_index(i, i)], count_);
    for (int i = 0; i < N; ++i) {
      for (int j = 0; j <= i; ++j) {
        factor[packed_index(i, j)] = Policy::matrix_entry(matrix_[packed_index(i, j)], count_, exponent[i] + exponent[j]);
      }
    }
    const Status status = ldlt_factor(factor, N, work.inverse_d, relative_floor);
    if (status != Status::kOk) return status;
    for (int r = 0; r < R; ++r) {
      for (int i = 0; i < N; ++i) work.y[i] = Policy::rhs_entry(rhs_[r][i], count_, exponent[i]);
      ldlt_solve(factor, work.inverse_d, N, work.y);
      for (int i = 0; i < N; ++i) x[r][i] = Policy::to_value(work.y[i], exponent[i]);
    }
    return Status::kOk;
  }

 private:
  Accum matrix_[packed_size(N)] = {};
  Accum rhs_[R][N] = {};
  uint32_t count_ = 0;
};

}  // namespace dg::fit

// Solving least-squares normal equations of fixed size from their sums, in any of the policies' scalar types.
#pragma once
#include <stdint.h>

#include "common/fit/dense_ldlt.h"

namespace dg::fit {

// The normal equations C^T C b = C^T z (Koivunen and Bajcsy 1992, eq. 8, [B] = [C^T C]^-1 C^T [S])
// of N unknowns, for one solve. The caller puts the sums of C^T C (packed lower triangle) in
// `factor` and those of C^T z in `y`, both through Policy::hold; `solve_normal_sums` converts them
// in place, so the sums need no memory of their own. Devices share one workspace between fits.
template <typename Policy, int N>
struct NormalWorkspace {
  using Solve = typename Policy::Solve;
  Solve factor[packed_size(N)];
  Solve inverse_d[N];
  Solve y[N];
  int exponent[N];

  void clear() {
    for (Solve& entry : factor) entry = Policy::hold(typename Policy::Accum{});
    for (Solve& entry : y) entry = Policy::hold(typename Policy::Accum{});
  }
  typename Policy::Accum held_matrix(int i, int j) const { return Policy::held(factor[packed_index(i, j)]); }
  void add_matrix(int i, int j, typename Policy::Accum sum) {
    Solve& entry = factor[packed_index(i, j)];
    entry = Policy::hold(Policy::held(entry) + sum);
  }
  void add_rhs(int i, typename Policy::Accum sum) { y[i] = Policy::hold(Policy::held(y[i]) + sum); }
};

// Solves the equations whose sums over `count` points `work` holds; the unknowns come back as
// Value (nm or mm) in x. The equations are first scaled symmetrically by powers of two so that every
// diagonal entry lies in [1/4, 1): exact in any type, it evens out the magnitudes that fixed point
// must hold (an outer control point of a net has a diagonal far below the others) and leaves the
// solution unchanged. kInvalidArgument: the sums leave some unknown undetermined.
template <typename Policy, int N>
Status solve_normal_sums(NormalWorkspace<Policy, N>& work, uint32_t count, typename Policy::Value (&x)[N],
                         typename Policy::Solve relative_floor) {
  if (count == 0) return Status::kNotReady;
  int* exponent = work.exponent;
  for (int i = 0; i < N; ++i) exponent[i] = Policy::diagonal_exponent(work.held_matrix(i, i), count);
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j <= i; ++j) {
      typename Policy::Solve& entry = work.factor[packed_index(i, j)];
      entry = Policy::matrix_entry(Policy::held(entry), count, exponent[i] + exponent[j]);
    }
  }
  const Status status = ldlt_factor(work.factor, N, work.inverse_d, relative_floor);
  if (status != Status::kOk) return status;
  for (int i = 0; i < N; ++i) work.y[i] = Policy::rhs_entry(Policy::held(work.y[i]), count, exponent[i]);
  ldlt_solve(work.factor, work.inverse_d, N, work.y);
  for (int i = 0; i < N; ++i) x[i] = Policy::to_value(work.y[i], exponent[i]);
  return Status::kOk;
}

}  // namespace dg::fit

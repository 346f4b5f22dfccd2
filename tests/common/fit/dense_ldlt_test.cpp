// The packed LDL^T solver: a known system in double and Q32.32, and singular systems refused.
#include "common/fit/dense_ldlt.h"

#include <CppUTest/TestHarness.h>

#include <cmath>

using namespace dg::fit;

TEST_GROUP(DenseLdlt){};

namespace {
// A = M M^T + I for a fixed M, packed; x_true = (1, -2, 3, 0.5); b = A x_true.
void make_system(double (&a)[10], double (&b)[4]) {
  const double m[4][4] = {{1, 0.2, 0, 0.1}, {0.3, 1, 0.5, 0}, {0, 0.4, 1, 0.2}, {0.1, 0, 0.3, 1}};
  const double x[4] = {1, -2, 3, 0.5};
  double full[4][4];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      full[i][j] = i == j ? 1.0 : 0.0;
      for (int k = 0; k < 4; ++k) full[i][j] += m[i][k] * m[j][k];
    }
  for (int i = 0; i < 4; ++i) {
    b[i] = 0;
    for (int j = 0; j < 4; ++j) b[i] += full[i][j] * x[j];
    for (int j = 0; j <= i; ++j) a[packed_index(i, j)] = full[i][j];
  }
}
}  // namespace

TEST(DenseLdlt, SolvesASymmetricPositiveDefiniteSystem) {
  double a[10], b[4], inverse_d[4];
  make_system(a, b);
  CHECK(dg::Status::kOk == ldlt_factor(a, 4, inverse_d, 1e-12));
  ldlt_solve(a, inverse_d, 4, b);
  DOUBLES_EQUAL(1.0, b[0], 1e-12);
  DOUBLES_EQUAL(-2.0, b[1], 1e-12);
  DOUBLES_EQUAL(3.0, b[2], 1e-12);
  DOUBLES_EQUAL(0.5, b[3], 1e-12);
}

TEST(DenseLdlt, FixedPointSolveAgreesWithDouble) {
  double a[10], b[4];
  make_system(a, b);
  dg::fx::Q32x32 qa[10], qb[4], inverse_d[4];
  for (int i = 0; i < 10; ++i) qa[i] = dg::fx::Q32x32::from_raw(std::llround(a[i] * 4294967296.0));
  for (int i = 0; i < 4; ++i) qb[i] = dg::fx::Q32x32::from_raw(std::llround(b[i] * 4294967296.0));
  CHECK(dg::Status::kOk == ldlt_factor(qa, 4, inverse_d, dg::fx::Q32x32::from_raw(1000)));
  ldlt_solve(qa, inverse_d, 4, qb);
  const double expected[4] = {1, -2, 3, 0.5};
  for (int i = 0; i < 4; ++i) DOUBLES_EQUAL(expected[i], qb[i].raw / 4294967296.0, 1e-8);
}

TEST(DenseLdlt, RefusesASingularMatrix) {
  // Rows 0 and 1 equal: rank 2 of 3.
  double a[6] = {1, 1, 1, 0.5, 0.5, 2};
  double inverse_d[3];
  CHECK(dg::Status::kInvalidArgument == ldlt_factor(a, 3, inverse_d, 1e-12));
}

TEST(DenseLdlt, RefusesAnIndefiniteMatrix) {
  double a[3] = {1, 2, 1};  // [[1, 2], [2, 1]]
  double inverse_d[2];
  CHECK(dg::Status::kInvalidArgument == ldlt_factor(a, 2, inverse_d, 1e-12));
}

// Weights from the sigma column: a spread the fit carries weighs an exact fit; a wider one, where
// the weighted fit comes out wrong, is refused with both ends named.
#include "host/fit/sigma_weights.h"

#include <CppUTest/TestHarness.h>

#include <cmath>

#include "host/fit/bspline_fit.h"
#include "host/fit/fit_error.h"
#include "host/fit/parameterize.h"

using namespace dg::host;

namespace {

// A bicubic polynomial of x and y: a cubic B-spline net over the table's rectangle holds it
// exactly, so any weights give the same surface and a difference is the arithmetic's.
double cubic_part(double x, double y) { return 1.0 + 0.002 * x * x - 0.00003 * x * x * y + 0.0001 * y * y * y / 30; }

// The largest |z| difference between a weighted 12 x 12 fit of a 41 x 31 grid and the true part
// at the grid's points, with every sigma `sigma_mm` but the middle point's, `middle_mm`.
double weighted_fit_error(double sigma_mm, double middle_mm) {
  PointCloud cloud;
  std::vector<double> sigmas;
  for (int j = 0; j < 31; ++j) {
    for (int i = 0; i < 41; ++i) {
      cloud.points.push_back({double(i), double(j), cubic_part(i, j)});
      sigmas.push_back(i == 20 && j == 15 ? middle_mm : sigma_mm);
    }
  }
  std::vector<double> weights;
  for (double s : sigmas) weights.push_back(1.0 / (s * s));
  const Parameters params = parameterize(cloud, Parameterization::kTableXy);
  LsqSpec spec;
  spec.knots_u = clamped_uniform_knots(12, 3);
  spec.knots_v = clamped_uniform_knots(12, 3);
  const BSplineSurface surface = fit_least_squares(cloud.points, params, &weights, spec);
  double worst = 0;
  for (size_t k = 0; k < cloud.points.size(); ++k) {
    const Point3 s = surface.evaluate(params.uv[k].u, params.uv[k].v);
    worst = std::fmax(worst, std::fabs(s.z - cloud.points[k].z));
  }
  return worst;
}

}  // namespace

TEST_GROUP(SigmaWeights){};

TEST(SigmaWeights, EachPointIsWeightedByOneOverItsSigmaSquared) {
  const SigmaWeights w = sigma_weights({0.001, 0.002, 0.0005});
  CHECK(w.problem.empty());
  LONGS_EQUAL(3, w.weights.size());
  DOUBLES_EQUAL(1e6, w.weights[0], 1e-6);
  DOUBLES_EQUAL(2.5e5, w.weights[1], 1e-6);
  DOUBLES_EQUAL(4e6, w.weights[2], 1e-6);
}

// At the limit the weighted fit is exact to the arithmetic; 10,000 times past it the same fit
// is far off (or its net found undetermined), which is why such sigmas are refused.
TEST(SigmaWeights, ASpreadUpToTheLimitWeighsAnExactFitAndAWiderOneIsRefusedWithBothEndsNamed) {
  CHECK(weighted_fit_error(0.01, 0.01 / kSigmaSpreadLimit) < 1e-7);  // 6e-9 mm measured
  CHECK(sigma_weights({0.01, 0.01 / kSigmaSpreadLimit, 0.01}).problem.empty());
  double past_limit = HUGE_VAL;
  try {
    past_limit = weighted_fit_error(100.0, 100.0 / (1e4 * kSigmaSpreadLimit));
  } catch (const FitError&) {
  }
  CHECK(past_limit > 1e-3);  // 1.2 mm measured
  const SigmaWeights refused = sigma_weights({0.001, 0.001, 1e-6, 0.001, 20.0});
  CHECK(refused.weights.empty());
  STRCMP_CONTAINS("the sigmas run from 1e-06 mm (point 3) to 20 mm (point 5), 2e+07 to 1", refused.problem.c_str());
  STRCMP_CONTAINS("--ignore-sigma", refused.problem.c_str());
}

TEST(SigmaWeights, ASigmaThatIsNotAPositiveNumberIsRefusedWithItsPoint) {
  STRCMP_CONTAINS("point 2's sigma is not a positive number", sigma_weights({0.001, 0.0}).problem.c_str());
  STRCMP_CONTAINS("point 1's sigma", sigma_weights({std::nan(""), 0.001}).problem.c_str());
  STRCMP_CONTAINS("point 3's sigma", sigma_weights({0.001, 0.001, HUGE_VAL}).problem.c_str());
}

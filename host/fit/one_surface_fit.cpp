// The single-surface tolerance fit of a table-XY scan, creases as knots.
#include "host/fit/one_surface_fit.h"

#include "host/fit/fit_error.h"
#include "host/fit/noise_estimate.h"
#include "host/fit/sigma_weights.h"

namespace dg::host {

ToleranceResult fit_one_surface(const PointCloud& cloud, double tolerance_mm, Parameters* params, Creases* creases) {
  *params = parameterize(cloud, Parameterization::kTableXy);
  std::vector<double> weights;
  if (cloud.sigma) {
    SigmaWeights from_sigma = sigma_weights(*cloud.sigma);
    if (!from_sigma.problem.empty()) {
      ToleranceResult refused;
      refused.reason = from_sigma.problem;
      return refused;
    }
    weights = std::move(from_sigma.weights);
  }
  *creases = detect_creases(cloud, *params, estimate_noise(cloud, *params));
  ToleranceOptions options;
  options.tolerance_mm = tolerance_mm;
  options.extra_knots_u = with_crease_knots({}, creases->u, options.degree_u);
  options.extra_knots_v = with_crease_knots({}, creases->v, options.degree_v);
  try {
    return fit_to_tolerance(cloud, *params, weights.empty() ? nullptr : &weights, options);
  } catch (const FitError& e) {
    ToleranceResult refused;
    refused.reason = e.what();
    return refused;
  }
}

}  // namespace dg::host

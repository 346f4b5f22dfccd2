// Weights from the sigma column, with the spread that double precision can carry checked.
#include "host/fit/sigma_weights.h"

#include <cmath>
#include <cstdio>

namespace dg::host {

SigmaWeights sigma_weights(const std::vector<double>& sigma_mm) {
  SigmaWeights out;
  size_t smallest = 0, largest = 0;
  for (size_t i = 0; i < sigma_mm.size(); ++i) {
    const double s = sigma_mm[i];
    if (!(s > 0) || !std::isfinite(s)) {
      out.problem = "point " + std::to_string(i + 1) + "'s sigma is not a positive number: it cannot weight the fit";
      return out;
    }
    if (s < sigma_mm[smallest]) smallest = i;
    if (s > sigma_mm[largest]) largest = i;
  }
  if (!sigma_mm.empty() && sigma_mm[largest] > kSigmaSpreadLimit * sigma_mm[smallest]) {
    char text[512];
    std::snprintf(text, sizeof text,
                  "the sigmas run from %g mm (point %zu) to %g mm (point %zu), %.3g to 1; weighted by 1/sigma^2, "
                  "points more than %g to 1 apart in sigma are beyond what the fit's normal equations carry (the "
                  "smallest sigmas' weights would swamp the rest and the fit would come out wrong): check the sigma "
                  "column's unit, or fit with --ignore-sigma",
                  sigma_mm[smallest], smallest + 1, sigma_mm[largest], largest + 1, sigma_mm[largest] / sigma_mm[smallest],
                  kSigmaSpreadLimit);
    out.problem = text;
    return out;
  }
  out.weights.reserve(sigma_mm.size());
  for (double s : sigma_mm) out.weights.push_back(1.0 / (s * s));
  return out;
}

}  // namespace dg::host

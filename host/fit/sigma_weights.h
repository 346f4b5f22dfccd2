// Least-squares weights 1/sigma^2 from the points' standard uncertainties, refused where the
// sigmas spread further apart than the fit's normal equations can carry in double precision.
#pragma once
#include <string>
#include <vector>

namespace dg::host {

// The largest ratio of one point's sigma to another's that a weighted fit accepts: the weights
// (1/sigma^2) then span 1e8. The arithmetic's error grows with the square of the ratio; fitting a
// bicubic polynomial (which a cubic net holds exactly) on a 41 x 31 grid with one point's sigma
// smaller than the rest, the 12 x 12 fit missed the polynomial by 6e-9 mm at a ratio of 1e4,
// 5e-5 mm at 1e6, 0.004 mm at 1e7 and 1.2 mm at 1e8 (sigma_weights_test.cpp). At 1e8 a tolerance
// fit of such a scan was refused with a false reason (a hole in the scan).
constexpr double kSigmaSpreadLimit = 1e4;

struct SigmaWeights {
  std::vector<double> weights;  // 1/sigma^2 per point; empty with a problem
  std::string problem;          // why the sigmas cannot weight a fit; empty when they can
};

// Weights for every point, or the problem: a sigma that is not a positive finite number (its point
// numbered from 1), or a spread beyond kSigmaSpreadLimit (the smallest and largest named).
SigmaWeights sigma_weights(const std::vector<double>& sigma_mm);

}  // namespace dg::host

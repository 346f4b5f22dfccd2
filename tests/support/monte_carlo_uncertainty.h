// The predicted standard uncertainty of a least-squares surface against the spread of refits of
// noisy replicas (the Monte Carlo method of GUM Supplement 1), on the simulated canister's true
// shape: shared by the test and the benchmark.
#pragma once
#include <cmath>
#include <random>
#include <vector>

#include "host/fit/bspline_fit.h"
#include "tests/support/part_scan.h"

namespace dg::test {

struct MonteCarloAgreement {
  int replicas = 0;
  double predicted_max_mm = 0, predicted_mean_mm = 0;
  double worst_relative = 0;  // max over the grid of |u_predicted / u_empirical - 1|
};

// The empirical standard deviation of the surface's height at the nodes of a grid x grid over
// the parameter domain, row by row, over `replicas` refits of `truth` with noise of `sigma` per
// point added (seeded by `seed`).
inline std::vector<double> replica_spread(const std::vector<host::Point3>& truth, const std::vector<double>& sigma,
                                          const std::vector<double>* weights, const host::Parameters& params,
                                          const host::LsqSpec& spec, int grid, int replicas, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  const size_t nodes = static_cast<size_t>(grid) * grid;
  std::vector<double> sum(nodes, 0.0), sum_sq(nodes, 0.0);
  for (int k = 0; k < replicas; ++k) {
    std::vector<host::Point3> noisy = truth;
    for (size_t i = 0; i < noisy.size(); ++i) noisy[i].z += sigma[i] * unit(rng);
    const host::BSplineSurface s = host::fit_least_squares(noisy, params, weights, spec);
    for (int r = 0; r < grid; ++r) {
      for (int c = 0; c < grid; ++c) {
        const double z = s.evaluate(static_cast<double>(c) / (grid - 1), static_cast<double>(r) / (grid - 1)).z;
        sum[static_cast<size_t>(r) * grid + c] += z;
        sum_sq[static_cast<size_t>(r) * grid + c] += z * z;
      }
    }
  }
  std::vector<double> spread(nodes);
  for (size_t g = 0; g < nodes; ++g) {
    const double mean = sum[g] / replicas;
    spread[g] = std::sqrt((sum_sq[g] - replicas * mean * mean) / (replicas - 1));
  }
  return spread;
}

// A 21 x 16 scan of the canister, a 9 x 8 bicubic net; unweighted every point has sigma 5 um,
// weighted sigma runs from 2 to 10 um across the part (a sigma column).
inline MonteCarloAgreement uncertainty_against_monte_carlo(bool weighted, int replicas) {
  const host::PointCloud truth = scan_part(noiseless_canister(21, 16), 1);
  const host::Parameters params = host::parameterize(truth, host::Parameterization::kTableXy);
  host::LsqSpec spec;
  spec.knots_u = host::clamped_uniform_knots(9, 3);
  spec.knots_v = host::clamped_uniform_knots(8, 3);
  std::vector<double> sigma(truth.points.size(), 0.005), weights;
  if (weighted) {
    for (size_t i = 0; i < sigma.size(); ++i) {
      sigma[i] = 0.002 + 0.008 * truth.points[i].x / 20.0;
      weights.push_back(1.0 / (sigma[i] * sigma[i]));
    }
  }
  const std::vector<double>* w = weighted ? &weights : nullptr;
  const host::BSplineSurface nominal = host::fit_least_squares(truth.points, params, w, spec);
  constexpr int kGrid = 11;
  const host::SurfaceUncertainty predicted = host::fit_uncertainty(truth.points, params, w, nominal, 0.005, kGrid);

  const std::vector<double> empirical = replica_spread(truth.points, sigma, w, params, spec, kGrid, replicas, 11);
  MonteCarloAgreement out;
  out.replicas = replicas;
  out.predicted_max_mm = predicted.max_mm;
  out.predicted_mean_mm = predicted.mean_mm;
  for (size_t g = 0; g < empirical.size(); ++g) {
    out.worst_relative = std::fmax(out.worst_relative, std::fabs(predicted.u_mm[g] / empirical[g] - 1.0));
  }
  return out;
}

}  // namespace dg::test

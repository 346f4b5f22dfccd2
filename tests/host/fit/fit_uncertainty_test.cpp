// The surface's predicted standard uncertainty against the spread of refits of noisy replicas (the
// Monte Carlo method of GUM Supplement 1), on the simulated canister's true shape.
#include <CppUTest/TestHarness.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "host/fit/bspline_fit.h"
#include "tests/support/part_scan.h"

using namespace dg::host;

namespace {

// The replica's heights at the uncertainty grid's nodes.
void heights_on_grid(const BSplineSurface& s, int grid, std::vector<double>& out) {
  out.resize(static_cast<size_t>(grid) * grid);
  for (int r = 0; r < grid; ++r) {
    for (int c = 0; c < grid; ++c) {
      out[static_cast<size_t>(r) * grid + c] = s.evaluate(static_cast<double>(c) / (grid - 1), static_cast<double>(r) / (grid - 1)).z;
    }
  }
}

void check_against_monte_carlo(bool weighted) {
  dg::test::PartScan part;
  part.kind = dg::sim::PartKind::kCanister;
  part.sigma_um = 0;  // the replicas add their own noise
  part.step_um = 0;
  part.nx = 21;
  part.ny = 16;
  const PointCloud truth = dg::test::scan_part(part, 1);
  const Parameters params = parameterize(truth, Parameterization::kTableXy);
  LsqSpec spec;
  spec.knots_u = clamped_uniform_knots(9, 3);
  spec.knots_v = clamped_uniform_knots(8, 3);
  // Unweighted: every point sigma 5 um. Weighted: sigma from 2 to 10 um across the part.
  std::vector<double> sigma(truth.points.size(), 0.005), weights;
  if (weighted) {
    for (size_t i = 0; i < sigma.size(); ++i) {
      sigma[i] = 0.002 + 0.008 * truth.points[i].x / 20.0;
      weights.push_back(1.0 / (sigma[i] * sigma[i]));
    }
  }
  const std::vector<double>* w = weighted ? &weights : nullptr;
  const BSplineSurface nominal = fit_least_squares(truth.points, params, w, spec);
  constexpr int kGrid = 11;
  const SurfaceUncertainty predicted = fit_uncertainty(truth.points, params, w, nominal, 0.005, kGrid);

  constexpr int kReplicas = 1000;
  std::mt19937 rng(11);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::vector<double> sum(kGrid * kGrid, 0.0), sum_sq(kGrid * kGrid, 0.0), z;
  for (int k = 0; k < kReplicas; ++k) {
    std::vector<Point3> noisy = truth.points;
    for (size_t i = 0; i < noisy.size(); ++i) noisy[i].z += sigma[i] * unit(rng);
    heights_on_grid(fit_least_squares(noisy, params, w, spec), kGrid, z);
    for (size_t g = 0; g < z.size(); ++g) sum[g] += z[g], sum_sq[g] += z[g] * z[g];
  }
  double worst = 0;
  for (size_t g = 0; g < sum.size(); ++g) {
    const double mean = sum[g] / kReplicas;
    const double empirical = std::sqrt((sum_sq[g] - kReplicas * mean * mean) / (kReplicas - 1));
    worst = std::fmax(worst, std::fabs(predicted.u_mm[g] / empirical - 1.0));
  }
  std::printf("\n  %s: predicted u max %.5f mean %.5f mm; against %d replicas worst relative difference %.1f %%",
              weighted ? "weighted (sigma column)" : "unweighted", predicted.max_mm, predicted.mean_mm, kReplicas, worst * 100);
  // 1000 replicas estimate a standard deviation to about 2.2 % (one sigma).
  CHECK(worst <= 0.10);
}

}  // namespace

TEST_GROUP(FitUncertainty){};

TEST(FitUncertainty, AgreesWithTheSpreadOfAThousandNoisyRefits) { check_against_monte_carlo(false); }

TEST(FitUncertainty, AgreesWithTheSpreadWhenEachPointHasItsOwnSigma) { check_against_monte_carlo(true); }

TEST(FitUncertainty, IsLargerWhereTheDataIsThinner) {
  // The edges of a net are held by points on one side only: their uncertainty exceeds the middle's.
  dg::test::PartScan part;
  part.kind = dg::sim::PartKind::kSaddle;
  part.sigma_um = 0;
  part.step_um = 0;
  const PointCloud c = dg::test::scan_part(part, 1);
  const Parameters p = parameterize(c, Parameterization::kTableXy);
  LsqSpec spec;
  spec.knots_u = clamped_uniform_knots(10, 3);
  spec.knots_v = clamped_uniform_knots(8, 3);
  const SurfaceUncertainty u = fit_uncertainty(c.points, p, nullptr, fit_least_squares(c.points, p, nullptr, spec), 0.002, 21);
  CHECK(u.u_mm[0] > 1.5 * u.u_mm[10 * 21 + 10]);
  CHECK(u.max_mm < 0.002);  // a least-squares surface averages: tighter than one point
}

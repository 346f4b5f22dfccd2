// The surface's predicted standard uncertainty against the spread of refits of noisy replicas (the
// Monte Carlo method of GUM Supplement 1), on the simulated canister's true shape.
#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "host/fit/bspline_fit.h"
#include "host/fit/knot_support.h"
#include "tests/support/monte_carlo_uncertainty.h"
#include "tests/support/part_scan.h"

using namespace dg::host;

namespace {

void check_against_monte_carlo(bool weighted) {
  const dg::test::MonteCarloAgreement m = dg::test::uncertainty_against_monte_carlo(weighted, 1000);
  std::printf("\n  %s: predicted u max %.5f mean %.5f mm; against %d replicas worst relative difference %.1f %%",
              weighted ? "weighted (sigma column)" : "unweighted", m.predicted_max_mm, m.predicted_mean_mm, m.replicas,
              m.worst_relative * 100);
  // 1000 replicas estimate a standard deviation to about 2.2 % (one sigma).
  CHECK(m.worst_relative <= 0.10);
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

TEST(FitUncertainty, ARegionsNetAgreesWithMonteCarloInsideItsTrim) {
  // The canister's points inside an ellipse, fitted over the whole box with the control points
  // beyond them placed by the membrane: the sandwich covariance against 1000 noisy refits, at the
  // grid nodes inside the ellipse (GUM Supplement 1).
  const PointCloud all = dg::test::scan_part(dg::test::noiseless_canister(21, 16), 1);
  auto inside = [](double x, double y) { return (x - 10) * (x - 10) / 64.0 + (y - 7.5) * (y - 7.5) / 36.0 < 1.0; };
  std::vector<Point3> truth;
  Parameters p;
  p.x_max = 20;
  p.y_max = 15;
  for (const Point3& q : all.points) {
    if (!inside(q.x, q.y)) continue;
    truth.push_back(q);
    p.uv.push_back({q.x / 20.0, q.y / 15.0});
  }
  LsqSpec spec;
  spec.knots_u = clamped_uniform_knots(8, 3);
  spec.knots_v = clamped_uniform_knots(7, 3);
  spec.fill_outside = true;
  const std::vector<char> outside = outside_control_points(spec.knots_u, 3, spec.knots_v, 3, SiteIndex(p.uv), kRegionMinProduct);
  CHECK(std::count(outside.begin(), outside.end(), 1) >= 4);  // the corners' control points are placed
  const BSplineSurface nominal = fit_least_squares(truth, p, nullptr, spec);
  constexpr int kGrid = 11;
  auto counts = [&](double u, double v) { return inside(20 * u, 15 * v); };
  const SurfaceUncertainty predicted = region_fit_uncertainty(truth, p, nullptr, nominal, 0.005, kGrid, counts);
  const std::vector<double> sigma(truth.size(), 0.005);
  const std::vector<double> empirical = dg::test::replica_spread(truth, sigma, nullptr, p, spec, kGrid, 1000, 5);
  double worst = 0;
  int nodes = 0;
  for (int r = 0; r < kGrid; ++r) {
    for (int c = 0; c < kGrid; ++c) {
      if (!counts(static_cast<double>(c) / (kGrid - 1), static_cast<double>(r) / (kGrid - 1))) continue;
      const size_t g = static_cast<size_t>(r) * kGrid + c;
      worst = std::fmax(worst, std::fabs(predicted.u_mm[g] / empirical[g] - 1.0));
      ++nodes;
    }
  }
  CHECK(nodes > 40);
  CHECK(predicted.max_mm > 0);
  CHECK(worst <= 0.10);
}

TEST(FitUncertainty, AKeptFitStatesTheSameUncertaintyAndTheSameSurfaceWithoutANewPass) {
  // `fit --ctrl` keeps its fit's factored equations for the uncertainty instead of building them
  // again from the points: the figures must be the same, with weights and without.
  dg::test::PartScan part;
  part.kind = dg::sim::PartKind::kCanister;
  part.sigma_um = 3;
  const PointCloud c = dg::test::scan_part(part, 2);
  const Parameters p = parameterize(c, Parameterization::kTableXy);
  LsqSpec spec;
  spec.knots_u = clamped_uniform_knots(9, 3);
  spec.knots_v = clamped_uniform_knots(8, 3);
  std::vector<double> weights(c.points.size());
  for (size_t k = 0; k < weights.size(); ++k) weights[k] = 1.0 / std::pow(0.002 + 0.001 * static_cast<double>(k % 5), 2);
  const std::vector<double>* weightings[] = {nullptr, &weights};
  for (const std::vector<double>* w : weightings) {
    const LeastSquaresFit kept = fit_least_squares_kept(c.points, p, w, spec);
    const BSplineSurface plain = fit_least_squares(c.points, p, w, spec);
    LONGS_EQUAL(plain.control.size(), kept.surface.control.size());
    for (size_t k = 0; k < plain.control.size(); ++k) DOUBLES_EQUAL(plain.control[k].z, kept.surface.control[k].z, 0.0);
    const SurfaceUncertainty again = fit_uncertainty(c.points, p, w, plain, 0.003, 21);
    const SurfaceUncertainty reused = fit_uncertainty(kept, 0.003, 21);
    CHECK(again.computed && reused.computed);
    CHECK(again.u_mm == reused.u_mm);
    DOUBLES_EQUAL(again.max_mm, reused.max_mm, 0.0);
  }
}

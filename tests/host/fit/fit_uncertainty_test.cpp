// The surface's predicted standard uncertainty against the spread of refits of noisy replicas (the
// Monte Carlo method of GUM Supplement 1), on the simulated canister's true shape.
#include <CppUTest/TestHarness.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "host/fit/bspline_fit.h"
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

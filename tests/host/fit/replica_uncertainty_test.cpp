// The Monte Carlo uncertainty (GUM Supplement 1) against an oracle it did not produce: for a
// least-squares fit, whose covariance is known in closed form, the refits' spread must agree.
#include "host/fit/replica_uncertainty.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <stdexcept>

#include "host/fit/bspline_fit.h"
#include "host/geometry/vec3.h"
#include "tests/support/part_scan.h"

using namespace dg::host;

namespace {

struct Case {
  std::vector<Point3> points;
  Parameters params;
  LsqSpec spec;
  BSplineSurface nominal;
};

Case canister_case() {
  Case c;
  c.points = dg::test::scan_part(dg::test::noiseless_canister(21, 16), 1).points;
  c.params.x_max = 20;
  c.params.y_max = 15;
  for (const Point3& q : c.points) c.params.uv.push_back({q.x / 20.0, q.y / 15.0});
  c.spec.knots_u = clamped_uniform_knots(7, 3);
  c.spec.knots_v = clamped_uniform_knots(6, 3);
  c.nominal = fit_least_squares(c.points, c.params, nullptr, c.spec);
  return c;
}

}  // namespace

TEST_GROUP(ReplicaUncertainty){};

TEST(ReplicaUncertainty, AgreesWithTheClosedFormCovarianceOfALeastSquaresFit) {
  const Case c = canister_case();
  constexpr double kSigma = 0.005;
  constexpr int kGrid = 11;
  const SurfaceUncertainty closed = fit_uncertainty(c.points, c.params, nullptr, c.nominal, kSigma, kGrid);
  ReplicaPlan plan;
  plan.replicas = 1000;
  plan.grid = kGrid;
  const SurfaceUncertainty mc = replica_uncertainty(
      c.points, std::vector<double>(c.points.size(), kSigma), c.nominal,
      [&](const std::vector<Point3>& noisy) { return fit_least_squares(noisy, c.params, nullptr, c.spec); }, plan);
  CHECK(mc.computed);
  DOUBLES_EQUAL(kSigma, mc.sigma_mm, 1e-12);
  double worst = 0;
  for (int g = 0; g < kGrid * kGrid; ++g) {
    // The height's uncertainty along the normal: u_z times the normal's z component.
    const double u = static_cast<double>(g % kGrid) / (kGrid - 1), v = static_cast<double>(g / kGrid) / (kGrid - 1);
    Point3 s, su, sv;
    c.nominal.evaluate(u, v, s, su, sv);
    const Point3 n = cross(su, sv);
    const double expected = closed.u_mm[static_cast<size_t>(g)] * std::fabs(n.z) / norm(n);
    worst = std::fmax(worst, std::fabs(mc.u_mm[static_cast<size_t>(g)] / expected - 1));
  }
  std::printf("\n  1000 least-squares refits against the closed-form covariance: worst |mc/closed - 1| %.1f %%", 100 * worst);
  CHECK(worst <= 0.10);
}

// Replica k's noise depends on the seed and k alone: the same figures on any number of cores.
TEST(ReplicaUncertainty, IsTheSameOnEveryRun) {
  const Case c = canister_case();
  ReplicaPlan plan;
  plan.replicas = 40;
  auto refit = [&](const std::vector<Point3>& noisy) { return fit_least_squares(noisy, c.params, nullptr, c.spec); };
  const std::vector<double> sigma(c.points.size(), 0.002);
  const SurfaceUncertainty a = replica_uncertainty(c.points, sigma, c.nominal, refit, plan);
  const SurfaceUncertainty b = replica_uncertainty(c.points, sigma, c.nominal, refit, plan);
  CHECK(a.computed);
  for (size_t g = 0; g < a.u_mm.size(); ++g) DOUBLES_EQUAL(a.u_mm[g], b.u_mm[g], 0);
}

// A method that refuses more than a tenth of the replicas gives no figure; fewer are left out.
TEST(ReplicaUncertainty, StatesNothingWhenTheMethodRefusesManyReplicas) {
  const Case c = canister_case();
  ReplicaPlan plan;
  plan.replicas = 40;
  const std::vector<double> sigma(c.points.size(), 0.002);
  int refused = 0;
  auto refuse_when = [&](double above) {
    return [&, above](const std::vector<Point3>& noisy) {
      if (noisy[0].z - c.points[0].z > above) throw std::runtime_error("refused");
      return fit_least_squares(noisy, c.params, nullptr, c.spec);
    };
  };
  CHECK(!replica_uncertainty(c.points, sigma, c.nominal, refuse_when(0.0), plan, &refused).computed);  // half refused
  CHECK(refused > 4);
  CHECK(replica_uncertainty(c.points, sigma, c.nominal, refuse_when(0.004), plan, &refused).computed);  // 2 sigma: ~1
  CHECK(refused <= 4);
}

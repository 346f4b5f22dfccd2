// The device's fit gains its standard uncertainty from the scan's points on the host: checked
// against the spread of the device's own fixed-point fits of noisy replicas (GUM Supplement 1).
#include <CppUTest/TestHarness.h>

#include <cmath>
#include <random>

#include "common/fit/height_field_fit.h"
#include "host/fit/device_fit_surface.h"
#include "host/fit/propagated_uncertainty.h"
#include "tests/support/part_scan.h"

using namespace dg::host;

namespace {

constexpr int kGrid = 21;  // fit_uncertainty's grid
constexpr double kSigmaMm = 0.005;

// The device's fit of `points` as the firmware makes it (common/fit in Q15 fixed point), then as
// the host reads it back.
template <typename Kind>
FittedSurface device_fit_of(const std::vector<Point3>& points, digitizer_DeviceFitModel model) {
  dg::fit::HeightFieldFit<dg::fit::FixedPolicy<15>, Kind> fit;
  const dg::fit::FitRegion region{0, 40000000, 0, 30000000};
  fit.begin(region);
  for (const Point3& p : points) {
    fit.add(static_cast<int32_t>(std::lround(p.x * 1e6)), static_cast<int32_t>(std::lround(p.y * 1e6)),
            static_cast<int32_t>(std::lround(p.z * 1e6)));
  }
  int32_t solved[Kind::kSide][Kind::kSide];
  typename dg::fit::HeightFieldFit<dg::fit::FixedPolicy<15>, Kind>::Workspace work;
  CHECK(fit.solve(solved, work) == dg::Status::kOk);
  digitizer_FitResult r = digitizer_FitResult_init_zero;
  r.status = digitizer_FitStatus_FIT_OK;
  r.model = model;
  r.side = Kind::kSide;
  r.points = fit.count();
  r.rejected = fit.rejected();
  r.has_x = r.has_y = true;
  r.x.min_nm = region.x_min_nm;
  r.x.max_nm = region.x_max_nm;
  r.y.min_nm = region.y_min_nm;
  r.y.max_nm = region.y_max_nm;
  r.z_nm_count = Kind::kSide * Kind::kSide;
  for (int i = 0; i < Kind::kSide; ++i)
    for (int j = 0; j < Kind::kSide; ++j) r.z_nm[i * Kind::kSide + j] = solved[i][j];
  return surface_from_device_fit(r, "test");
}

template <typename Kind>
void check_against_monte_carlo(digitizer_DeviceFitModel model) {
  const PointCloud truth = dg::test::scan_part(dg::test::noiseless_canister(), 1);
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, kSigmaMm);
  constexpr int kReplicas = 1000;
  std::vector<double> sum(kGrid * kGrid, 0.0), sum2(kGrid * kGrid, 0.0);
  PointCloud noisy = truth;
  for (int k = 0; k < kReplicas; ++k) {
    for (size_t i = 0; i < truth.points.size(); ++i) noisy.points[i].z = truth.points[i].z + noise(rng);
    const FittedSurface f = device_fit_of<Kind>(noisy.points, model);
    for (int r = 0; r < kGrid; ++r)
      for (int c = 0; c < kGrid; ++c) {
        const double z = f.surface.evaluate(static_cast<double>(c) / (kGrid - 1), static_cast<double>(r) / (kGrid - 1)).z;
        sum[r * kGrid + c] += z;
        sum2[r * kGrid + c] += z * z;
      }
  }
  // The last replica stands for the scan the user has: the host's report of the device's fit of it.
  FittedSurface f = device_fit_of<Kind>(noisy.points, model);
  const std::string why_not = add_scan_to_device_fit(f, noisy, static_cast<uint32_t>(noisy.points.size()), 0);
  STRCMP_EQUAL("", why_not.c_str());
  CHECK(f.has_fit);
  CHECK(f.uncertainty.computed);
  LONGS_EQUAL(kGrid, f.uncertainty.rows);
  // The noise estimate is its own figure (tested elsewhere); the covariance is checked per unit
  // of the sigma it was propagated from.
  double worst = 0;
  for (int g = 0; g < kGrid * kGrid; ++g) {
    const double mean = sum[g] / kReplicas;
    const double empirical = std::sqrt((sum2[g] / kReplicas - mean * mean) * kReplicas / (kReplicas - 1));
    const double predicted = f.uncertainty.u_mm[g] / f.uncertainty.sigma_mm * kSigmaMm;
    worst = std::fmax(worst, std::fabs(predicted / empirical - 1));
  }
  std::printf("\n  device %s fit: predicted u against %d fixed-point refits, worst |predicted/empirical - 1| %.1f %%",
              model == digitizer_DeviceFitModel_DEVICE_FIT_NET ? "5 x 5 net" : "Bezier", kReplicas, 100 * worst);
  CHECK(worst <= 0.10);
}

}  // namespace

TEST_GROUP(DeviceFitUncertainty){};

TEST(DeviceFitUncertainty, TheBezierPatchsAgreesWithTheSpreadOfTheDevicesOwnRefits) {
  check_against_monte_carlo<dg::fit::BezierBasis>(digitizer_DeviceFitModel_DEVICE_FIT_BEZIER);
}

TEST(DeviceFitUncertainty, TheNetsAgreesWithTheSpreadOfTheDevicesOwnRefits) {
  check_against_monte_carlo<dg::fit::UniformCubicBasis<5>>(digitizer_DeviceFitModel_DEVICE_FIT_NET);
}

// The device's counts must say it fitted exactly the scan's points, or no uncertainty is stated.
TEST(DeviceFitUncertainty, IsNotStatedWhenTheDeviceLeftPointsOut) {
  dg::test::PartScan part;
  part.kind = dg::sim::PartKind::kCanister;
  const PointCloud scan = dg::test::scan_part(part, 2);
  FittedSurface f = device_fit_of<dg::fit::BezierBasis>(scan.points, digitizer_DeviceFitModel_DEVICE_FIT_BEZIER);
  STRCMP_CONTAINS("left 3 points out", add_scan_to_device_fit(f, scan, 1268, 3).c_str());
  CHECK(!f.uncertainty.computed);
  CHECK(f.has_fit);  // the distances of the scan's points to it are still a report
  STRCMP_CONTAINS("fitted 1000 points", add_scan_to_device_fit(f, scan, 1000, 0).c_str());
  CHECK(!f.uncertainty.computed);
}

// The device's net has unclamped knots: its corner control points lie beyond the rectangle, so a
// table point's parameters come from the Greville abscissae, not the corners (read as the domain's
// ends, inspect measured against the net 20 mm away from where it is).
TEST(DeviceFitUncertainty, TheDevicesNetIsReadAboveTheRightTablePoint) {
  dg::test::PartScan part;
  part.kind = dg::sim::PartKind::kCanister;
  const PointCloud scan = dg::test::scan_part(part, 3);
  const FittedSurface f = device_fit_of<dg::fit::UniformCubicBasis<5>>(scan.points, digitizer_DeviceFitModel_DEVICE_FIT_NET);
  for (const Point2 q : {Point2{0, 0}, Point2{12.5, 7}, Point2{40, 30}}) {
    const Point3 p = point_above(f.surface, q.x, q.y);
    DOUBLES_EQUAL(q.x, p.x, 1e-9);
    DOUBLES_EQUAL(q.y, p.y, 1e-9);
  }
}

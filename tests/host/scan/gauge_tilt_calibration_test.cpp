// The gauge's tilt from a reference sphere, against readings made in closed form (the line along
// the leaning plunger meets the ball), with and without noise, and the sphere fits it refuses.
#include <CppUTest/TestHarness.h>

#include <cmath>
#include <random>
#include <string>

#include "host/scan/gauge_tilt_calibration.h"
#include "host/scan/table_calibration.h"

using namespace dg::host;

namespace {

constexpr double kRadius = 12.7, kCx = 31.0, kCy = 22.0, kCz = 9.0;

// The reading of a gauge leaning (tx, ty) rad at table position (x, y) over the ball, or the 2 mm
// base where the line misses it: r along (sin tx, sin ty, cos) from (x, y, 0).
double reading(double tx, double ty, double x, double y) {
  const double sx = std::sin(tx), sy = std::sin(ty), c = std::sqrt(1 - sx * sx - sy * sy);
  const double px = x - kCx, py = y - kCy, pz = -kCz;
  const double b = px * sx + py * sy + pz * c, q = px * px + py * py + pz * pz - kRadius * kRadius;
  return b * b - q >= 0 ? -b + std::sqrt(b * b - q) : 2.0 / c;
}

// The sphere scanned at `step_mm` over its footprint and 3 mm around, readings rounded to 1 um.
PointCloud sphere_scan(double tx, double ty, double step_mm, double noise_mm, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> noise(0.0, noise_mm);
  PointCloud cloud;
  for (double y = kCy - 13; y <= kCy + 13; y += step_mm) {
    for (double x = kCx - 13; x <= kCx + 13; x += step_mm) {
      const double z = reading(tx, ty, x, y) + (noise_mm > 0 ? noise(random) : 0.0);
      cloud.points.push_back({x, y, std::round(z * 1e3) * 1e-3});
    }
  }
  return cloud;
}

std::string refusal(const PointCloud& cloud, double diameter_mm) {
  try {
    calibrate_gauge_tilt(cloud, diameter_mm, "sphere.scan");
  } catch (const CalibrationError& error) {
    return error.what();
  }
  return "";
}

}  // namespace

TEST_GROUP(GaugeTiltCalibration){};

TEST(GaugeTiltCalibration, ALeanOfAFewMilliradiansIsFoundFromTheSpheresCapAndTheCentreWithIt) {
  const double tilts[][2] = {{3e-3, -2e-3}, {0, 0}, {-20e-3, 12e-3}};
  for (const auto& t : tilts) {
    const GaugeTilt g = calibrate_gauge_tilt(sphere_scan(t[0], t[1], 0.5, 0, 1), 2 * kRadius, "sphere.scan");
    // Readings rounded to 1 um: the rounding is the only noise, about 0.29 um.
    DOUBLES_EQUAL(t[0] * 1e6, g.tilt_x_urad, 4 * g.u_tilt_x_urad + 1);
    DOUBLES_EQUAL(t[1] * 1e6, g.tilt_y_urad, 4 * g.u_tilt_y_urad + 1);
    CHECK(g.u_tilt_x_urad < 30 && g.u_tilt_y_urad < 30);
    DOUBLES_EQUAL(kCx, g.centre_mm[0], 0.002);
    DOUBLES_EQUAL(kCy, g.centre_mm[1], 0.002);
    DOUBLES_EQUAL(kCz, g.centre_mm[2], 0.002);
    CHECK(g.residual_rms_mm < 0.0005);
    CHECK(g.points > 1000);
  }
}

// GUM Supplement 1's check of a stated uncertainty: refit many noisy replicas and compare the
// spread of the results with the u each fit states.
TEST(GaugeTiltCalibration, TheStatedUncertaintyMatchesTheSpreadOfRepeatedCalibrations) {
  constexpr int kReplicas = 200;
  double sum[2] = {}, sum_sq[2] = {}, stated[2] = {};
  for (int k = 0; k < kReplicas; ++k) {
    const GaugeTilt g = calibrate_gauge_tilt(sphere_scan(3e-3, -2e-3, 1.0, 0.002, 100 + k), 2 * kRadius, "sphere.scan");
    const double v[2] = {g.tilt_x_urad, g.tilt_y_urad}, u[2] = {g.u_tilt_x_urad, g.u_tilt_y_urad};
    for (int i = 0; i < 2; ++i) sum[i] += v[i], sum_sq[i] += v[i] * v[i], stated[i] += u[i] / kReplicas;
  }
  for (int i = 0; i < 2; ++i) {
    const double mean = sum[i] / kReplicas;
    const double spread = std::sqrt((sum_sq[i] - kReplicas * mean * mean) / (kReplicas - 1));
    std::printf("\n  tilt %c: mean %.1f urad (true %.0f), spread %.1f, stated u %.1f", i == 0 ? 'x' : 'y', mean,
                i == 0 ? 3000.0 : -2000.0, spread, stated[i]);
    // 200 replicas know a standard deviation to about 5 %; 15 % allows three of those.
    DOUBLES_EQUAL(1.0, spread / stated[i], 0.15);
    DOUBLES_EQUAL(i == 0 ? 3000 : -2000, mean, 4 * stated[i] / std::sqrt(kReplicas));  // no bias
  }
}

// The travel map's own uncertainty: a map 1 um uncertain at each 5 mm node may carry a slope
// under the sphere that the fit takes for a lean. Readings with the nodes' errors drawn afresh
// (independent, 1 um) scatter as the map part of u says, within 15 % over 200 maps.
TEST(GaugeTiltCalibration, TheTravelMapsUncertaintyIsCarriedIntoTheTilts) {
  TableCalibration map;
  map.x0_mm = 15, map.y0_mm = 5, map.step_x_mm = map.step_y_mm = 5, map.nx = map.ny = 7;
  map.z_error_mm.assign(49, 0.0);
  map.u_mm.assign(49, 0.001);
  constexpr int kMaps = 200;
  double sum_sq[2] = {}, stated[2] = {};
  std::mt19937 random(7);
  std::normal_distribution<double> node_error(0.0, 0.001);
  for (int k = 0; k < kMaps; ++k) {
    TableCalibration truth = map;  // what the travel really adds, within the map's u of its zero
    for (double& e : truth.z_error_mm) e = node_error(random);
    PointCloud cloud;
    for (double y = kCy - 13; y <= kCy + 13; y += 0.5) {
      for (double x = kCx - 13; x <= kCx + 13; x += 0.5) cloud.points.push_back({x, y, reading(3e-3, -2e-3, x, y) + truth.z_error_at(x, y)});
    }
    const GaugeTilt g = calibrate_gauge_tilt(cloud, 2 * kRadius, "sphere.scan", &map);
    const double error[2] = {g.tilt_x_urad - 3000, g.tilt_y_urad + 2000}, u[2] = {g.u_map_x_urad, g.u_map_y_urad};
    for (int i = 0; i < 2; ++i) sum_sq[i] += error[i] * error[i], stated[i] += u[i] / kMaps;
    DOUBLES_EQUAL(std::hypot(g.u_noise_x_urad, g.u_map_x_urad), g.u_tilt_x_urad, 1e-9);
  }
  for (int i = 0; i < 2; ++i) {
    const double spread = std::sqrt(sum_sq[i] / kMaps);
    std::printf("\n  tilt %c from the map alone: spread %.1f urad, stated %.1f", i == 0 ? 'x' : 'y', spread, stated[i]);
    CHECK(stated[i] > 20);  // 1 um over a 20 mm cap is tens of microradians: not negligible
    DOUBLES_EQUAL(1.0, spread / stated[i], 0.15);
  }
}

TEST(GaugeTiltCalibration, ReadingsThatHoldNoSuchSphereAreRefusedWithTheReason) {
  STRCMP_CONTAINS("readings lie on the sphere's cap", refusal(sphere_scan(0, 0, 4.0, 0, 1), 2 * kRadius).c_str());
  STRCMP_CONTAINS("the certificate says 20.000 mm", refusal(sphere_scan(0, 0, 0.5, 0, 1), 20).c_str());
  PointCloud flat;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) flat.points.push_back({0.5 * i, 0.5 * j, 5.0});
  STRCMP_CONTAINS("reach only 0.00 mm below it", refusal(flat, 2 * kRadius).c_str());
  // A ball read with 20 um of scatter (a dirty ball, a loose stand) is no calibration.
  STRCMP_CONTAINS("mm RMS off a 25.400 mm sphere", refusal(sphere_scan(0, 0, 0.5, 0.020, 1), 2 * kRadius).c_str());
  STRCMP_CONTAINS("diameter must lie between", refusal(sphere_scan(0, 0, 0.5, 0, 1), std::nan("")).c_str());
  STRCMP_CONTAINS("no readings", refusal(PointCloud{}, 2 * kRadius).c_str());
}

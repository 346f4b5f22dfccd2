// The LTS filter's window models: a subset that is already the h smallest of a window is told
// without a selection; on a steep flank the model is fitted in its tangent plane.
#include "host/scan/lts_models.h"

#include <CppUTest/TestHarness.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "hw/sim/parts.h"

using dg::host::lts::keeps_mask;
using dg::host::lts::loo_model;
using dg::host::lts::LooModel;
using dg::host::lts::Ranked;

TEST_GROUP(LtsModels){};

// Against nth_element on random windows, ties in the residual included (readings in whole
// micrometres make them): the mask of the h smallest is kept, and any other mask of h is not.
TEST(LtsModels, KeepsMaskAgreesWithTheSelectionOfTheSmallest) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = 6 + static_cast<int>(rng() % 59);
    const int h = 1 + static_cast<int>(rng() % static_cast<unsigned>(n));
    std::vector<Ranked> ranked;
    for (int m = 0; m < n; ++m) {
      // Few distinct residuals, so that ties are common; point numbers in shuffled order.
      ranked.push_back({static_cast<double>(rng() % 5), static_cast<size_t>(rng() % 1000) * 64 + static_cast<size_t>(m),
                        static_cast<unsigned>(m)});
    }
    std::vector<Ranked> selected = ranked;
    std::nth_element(selected.begin(), selected.begin() + (h - 1), selected.end());
    uint64_t smallest = 0;
    for (int m = 0; m < h; ++m) smallest |= uint64_t{1} << selected[static_cast<size_t>(m)].position;
    CHECK(keeps_mask(ranked, smallest));
    if (h == n) continue;
    // Swap one place in for one out: no longer the h smallest (point numbers break every tie).
    const unsigned in = selected[static_cast<size_t>(rng() % static_cast<unsigned>(h))].position;
    const unsigned out = selected[static_cast<size_t>(h + static_cast<int>(rng() % static_cast<unsigned>(n - h)))].position;
    CHECK_FALSE(keeps_mask(ranked, (smallest & ~(uint64_t{1} << in)) | uint64_t{1} << out));
  }
}

namespace {

// The reference sphere's 5 x 5 window at 1 mm about (cx, cy), its true heights rounded to the
// gauge's 1 um, a seeded noise of `sigma_mm` added; the centre is point 12.
std::vector<dg::host::Point3> sphere_window(double cx, double cy, double sigma_mm, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, sigma_mm);
  std::vector<dg::host::Point3> points;
  for (int dy = -2; dy <= 2; ++dy) {
    for (int dx = -2; dx <= 2; ++dx) {
      const double z = dg::sim::shape_height_mm(dg::sim::PartKind::kSphere, cx + dx, cy + dy) + noise(rng);
      points.push_back({cx + dx, cy + dy, std::round(z * 1000) / 1000});
    }
  }
  return points;
}

}  // namespace

TEST(LtsModels, AWindowOnASteepFlankIsModelledInItsTangentPlane) {
  // 10 to 11 mm from the sphere's axis (slopes 1.5 to 1.8) at 2 um of noise: the upright cubic
  // misses the centre's true height by over 20 um, more than a 10 sigma outlier; the tilted model
  // follows the flank to its trimmed scale of 1.3 to 3.6 um and misses it by under 10 um. (With the
  // gauge's noise of 2 um and the point left out, a few micrometres of that is the fit's own.)
  for (const auto& [cx, cy] :
       {std::pair{31.0, 15.0}, std::pair{27.0, 23.0}, std::pair{9.0, 15.0}, std::pair{12.0, 8.0}, std::pair{20.0, 26.0}}) {
    const std::vector<dg::host::Point3> points = sphere_window(cx, cy, 0.002, 5);
    std::vector<size_t> others;
    for (size_t j = 0; j < points.size(); ++j) {
      if (j != 12) others.push_back(j);
    }
    std::vector<double> reference(points.size());
    for (size_t j = 0; j < points.size(); ++j) reference[j] = points[j].z;
    const LooModel upright = loo_model(points, others, 12, reference, 3);
    const LooModel tilted = loo_model(points, others, 12, reference, 3, 0.7, nullptr, true);
    const double truth = dg::sim::shape_height_mm(dg::sim::PartKind::kSphere, cx, cy);
    CHECK(upright.ok && tilted.ok);
    CHECK_FALSE(upright.polynomial.tilted);
    CHECK(tilted.polynomial.tilted);
    CHECK(tilted.scale < dg::host::lts::kTiltKeep * upright.scale);
    CHECK(tilted.scale < 0.005);
    CHECK(std::fabs(upright.prediction - truth) > 0.02);
    CHECK(std::fabs(tilted.prediction - truth) < 0.01);
    CHECK(std::fabs(upright.prediction - truth) > 2 * std::fabs(tilted.prediction - truth));
  }
}

TEST(LtsModels, AWindowOnTheSpheresCapStaysUpright) {
  // 3 mm from the axis the slope is 0.24, under kTiltSlope: the model is the upright one.
  const std::vector<dg::host::Point3> points = sphere_window(23, 15, 0.002, 5);
  std::vector<size_t> others;
  for (size_t j = 0; j < points.size(); ++j) {
    if (j != 12) others.push_back(j);
  }
  std::vector<double> reference(points.size());
  for (size_t j = 0; j < points.size(); ++j) reference[j] = points[j].z;
  const LooModel with = loo_model(points, others, 12, reference, 3, 0.7, nullptr, true);
  const LooModel without = loo_model(points, others, 12, reference, 3);
  CHECK_FALSE(with.polynomial.tilted);
  DOUBLES_EQUAL(without.prediction, with.prediction, 0);
  DOUBLES_EQUAL(without.scale, with.scale, 0);
}

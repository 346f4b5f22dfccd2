// Surface characterization (Koivunen and Bajcsy 1992, section 5.3): the HK types of simple shapes, regions of a
// bump on a plate, the net it suggests, and the crease of a step.
#include "host/fit/characterize.h"

#include <CppUTest/TestHarness.h>

#include <cmath>
#include <functional>
#include <random>

#include "host/fit/fit_error.h"

using namespace dg::host;

namespace {

PointCloud grid(const std::function<double(double, double)>& z, int side = 41, double noise = 0) {
  PointCloud c;
  c.line = std::vector<uint32_t>{};
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0, noise > 0 ? noise : 1);
  for (int j = 0; j < side; ++j) {
    for (int i = 0; i < side; ++i) {
      const double x = i, y = j;
      c.points.push_back({x, y, z(x, y) + (noise > 0 ? n(rng) : 0)});
      c.line->push_back(static_cast<uint32_t>(j));
    }
  }
  return c;
}

// The type most points have.
SurfaceType majority(const Characterization& c) {
  int best = 0;
  for (int t = 1; t < 8; ++t) {
    if (c.type_counts[t] > c.type_counts[best]) best = t;
  }
  return static_cast<SurfaceType>(best);
}

}  // namespace

TEST_GROUP(Characterize){};

TEST(Characterize, NamesTheTypesOfSimpleShapes) {
  struct Case {
    const char* name;
    std::function<double(double, double)> z;
    SurfaceType type;
  } cases[] = {
      {"dome", [](double x, double y) { return -0.01 * ((x - 20) * (x - 20) + (y - 20) * (y - 20)); }, SurfaceType::kPeak},
      {"bowl", [](double x, double y) { return 0.01 * ((x - 20) * (x - 20) + (y - 20) * (y - 20)); }, SurfaceType::kPit},
      {"ridge", [](double x, double) { return -0.01 * (x - 20) * (x - 20); }, SurfaceType::kRidge},
      {"valley", [](double, double y) { return 0.01 * (y - 20) * (y - 20); }, SurfaceType::kValley},
      {"plane", [](double x, double y) { return 0.1 * x - 0.2 * y; }, SurfaceType::kFlat},
  };
  for (const Case& c : cases) {
    const Characterization r = characterize(grid(c.z, 41, 0.0005));
    STRCMP_EQUAL(surface_type_name(c.type), surface_type_name(majority(r)));
  }
  // A saddle has K < 0 everywhere: saddle ridge or valley by the sign of H, minimal where H ~ 0.
  const Characterization saddle = characterize(grid([](double x, double y) { return 0.01 * ((x - 20) * (x - 20) - (y - 20) * (y - 20)); }, 41, 0.0005));
  const size_t negative_k = saddle.type_counts[static_cast<int>(SurfaceType::kSaddleRidge)] +
                            saddle.type_counts[static_cast<int>(SurfaceType::kSaddleValley)] +
                            saddle.type_counts[static_cast<int>(SurfaceType::kMinimal)];
  CHECK(negative_k > saddle.points.size() * 9 / 10);
  CHECK(saddle.type_counts[static_cast<int>(SurfaceType::kMinimal)] > 0);
}

TEST(Characterize, CurvaturesOfASphereCap) {
  // z = sqrt(R^2 - r^2) with R = 100: H = -1/R, K = 1/R^2 everywhere.
  const Characterization r = characterize(grid([](double x, double y) {
    return std::sqrt(10000 - (x - 20) * (x - 20) - (y - 20) * (y - 20));
  }));
  const PointCharacter& c = r.points[20 * 41 + 20];
  DOUBLES_EQUAL(-0.01, c.mean_curvature, 1e-5);
  DOUBLES_EQUAL(1e-4, c.gaussian_curvature, 1e-6);
  LONGS_EQUAL(static_cast<int>(SurfaceType::kPeak), static_cast<int>(c.type));
}

TEST(Characterize, ABumpOnAPlateIsRegionsAndAsksForAFinerNet) {
  auto plate = [](double, double) { return 1.0; };
  auto bump = [](double x, double y) {
    const double r2 = (x - 20) * (x - 20) + (y - 20) * (y - 20);
    return 1.0 + 3.0 * std::exp(-r2 / 30.0);
  };
  const Characterization flat = characterize(grid(plate, 41, 0.0005));
  const Characterization bumped = characterize(grid(bump, 41, 0.0005));
  LONGS_EQUAL(1, flat.significant_regions);
  LONGS_EQUAL(4, flat.suggested_control_x);
  // Plate, the bump's flank (a valley ring around a peak, saddles between): several regions.
  CHECK(bumped.significant_regions >= 3);
  CHECK(bumped.regions_across_x >= 3);
  CHECK(bumped.suggested_control_x > flat.suggested_control_x);
  CHECK(bumped.suggested_control_y > flat.suggested_control_y);
}

TEST(Characterize, FindsTheStepAcrossAScan) {
  auto step = [](double x, double) { return x < 20.5 ? 0.0 : 2.0; };
  const Characterization r = characterize(grid(step, 41, 0.002));
  CHECK(!r.creases_x_mm.empty());
  for (double x : r.creases_x_mm) DOUBLES_EQUAL(20.5, x, 1.0);
}

TEST(Characterize, RefusesTooFewPoints) {
  PointCloud c;
  for (int i = 0; i < 10; ++i) c.points.push_back({static_cast<double>(i), static_cast<double>(i % 3), 0});
  CHECK_THROWS(FitError, characterize(c));
}

// A grid of few lines: a cylinder across eight lines is ridges, valleys and flats (the noise now
// estimated, not taken for curvature), and the net suggested has no more control points along a
// direction than the points take positions; two lines determine no quadratic and no cubic net, and
// say so instead of calling every point flat.
TEST(Characterize, AGridOfFewLinesGetsNoTypeItCannotShowNorANetItCannotDetermine) {
  std::mt19937 rng(6);
  std::normal_distribution<double> noise(0.0, 0.002);
  auto rows = [&](int lines) {
    PointCloud c;  // no line numbers, as from a CSV of x, y, z
    for (int i = 0; i < 50; ++i) {
      for (int j = 0; j < lines; ++j) c.points.push_back({double(i), double(j), std::sin(i / 5.0) + noise(rng)});
    }
    return c;
  };
  const Characterization eight = characterize(rows(8));
  LONGS_EQUAL(0, eight.undetermined);
  size_t curved_both_ways = 0;
  for (SurfaceType t : {SurfaceType::kPeak, SurfaceType::kPit, SurfaceType::kSaddleRidge, SurfaceType::kSaddleValley}) {
    curved_both_ways += eight.type_counts[static_cast<int>(t)];
  }
  CHECK(curved_both_ways <= 8);  // 2 %: 4 measured; 399 of 400 on a like scan before the noise was estimated
  CHECK(eight.type_counts[static_cast<int>(SurfaceType::kRidge)] > 150);
  CHECK(eight.type_counts[static_cast<int>(SurfaceType::kValley)] > 80);
  LONGS_EQUAL(8, eight.distinct_y);
  CHECK(eight.suggested_control_y >= 4 && eight.suggested_control_y <= 8);
  const Characterization two = characterize(rows(2));
  LONGS_EQUAL(100, two.undetermined);
  LONGS_EQUAL(0, two.regions);
  LONGS_EQUAL(0, two.suggested_control_y);
  LONGS_EQUAL(50, two.distinct_x);
}

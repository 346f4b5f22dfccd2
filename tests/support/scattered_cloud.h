// Scattered points (no scan lines) over a rectangle at random places, with normal noise in z.
#pragma once
#include <cstddef>
#include <random>

#include "host/scan/point_reader.h"

namespace dg::test {

// `count` points uniform over [0, width] x [0, depth] mm (seeded, so runs repeat), z = height(x, y)
// plus noise of `sigma_mm`.
template <typename Height>
host::PointCloud scattered_cloud(size_t count, double width_mm, double depth_mm, unsigned seed, double sigma_mm, Height height) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> along(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, sigma_mm);
  host::PointCloud c;
  c.points.reserve(count);
  for (size_t k = 0; k < count; ++k) {
    const double x = width_mm * along(rng), y = depth_mm * along(rng);
    c.points.push_back({x, y, height(x, y) + (sigma_mm > 0 ? noise(rng) : 0.0)});
  }
  return c;
}

}  // namespace dg::test

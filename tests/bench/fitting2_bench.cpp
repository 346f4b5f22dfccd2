// Fitting core II benchmarks on 1e4 and 1e5 points: Hermite surfaces through a grid with normals,
// Hlavova's (2021) curves, superquadric recovery, characterization; one core, wall time with steady_clock.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "host/fit/characterize.h"
#include "host/fit/hermite_fit.h"
#include "host/fit/profile_curve.h"
#include "host/fit/superquadric.h"
#include "host/geometry/vec3.h"

using namespace dg::host;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A dome of radius 60 over a side x side grid spanning 60 mm, with its normals.
HermiteGrid dome(int side) {
  HermiteGrid g;
  g.rows = g.cols = side;
  for (int r = 0; r < side; ++r) {
    for (int c = 0; c < side; ++c) {
      const double x = -30 + 60.0 * c / (side - 1), y = -30 + 60.0 * r / (side - 1);
      const Point3 p{x, y, std::sqrt(3600 - x * x - y * y)};
      g.points.push_back(p);
      g.normals.push_back((1.0 / 60) * p);
    }
  }
  return g;
}

std::vector<Point3> profile(size_t n) {
  std::vector<Point3> p;
  for (size_t k = 0; k < n; ++k) {
    const double x = -25 + 50.0 * static_cast<double>(k) / static_cast<double>(n - 1);
    p.push_back({x, 0, 25 + 0.0156 * x * x - 0.313 * x + 0.2 * std::sin(x / 3)});
  }
  return p;
}

std::vector<Point3> pin(size_t n) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> along(-10, 10), angle(0, 2 * M_PI);
  std::normal_distribution<double> noise(0, 0.002);
  std::vector<Point3> p;
  for (size_t k = 0; k < n; ++k) {
    const double a = angle(rng);
    p.push_back({4 * std::cos(a) + noise(rng), 4 * std::sin(a) + noise(rng), along(rng)});
  }
  return p;
}

}  // namespace

int main() {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  for (int side : {100, 316}) {
    const HermiteGrid g = dome(side);
    const auto t0 = std::chrono::steady_clock::now();
    const HermiteResult r = fit_hermite(g);
    const double s = seconds_since(t0);
    double worst = 0;
    for (int k = 0; k < 200; ++k) {
      const double u = r.u.back() * (k % 20 + 0.5) / 20, v = r.v.back() * (k / 20 + 0.5) / 10;
      worst = std::fmax(worst, std::fabs(norm(r.surface.evaluate(u, v)) - 60));
    }
    std::printf("hermite %dx%d grid (%d points): %.3f s, %d x %d control points, max radial error %.2e mm\n", side, side,
                side * side, s, r.surface.count_u, r.surface.count_v, worst);
  }
  for (size_t n : {10000u, 100000u}) {
    const std::vector<Point3> p = profile(n);
    auto t0 = std::chrono::steady_clock::now();
    const CeCurve ce = curve_within_uncertainty(p, 0.0003);
    const double ce_s = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    const DistanceStats d = distance_stats(curve_distances(ce.curve, p));
    std::printf("ce curve %zu points: %.3f s, distances along normals %.3f s (mean %.6f max %.6f mm)\n", n, ce_s,
                seconds_since(t0), d.mean, d.max);
  }
  for (size_t n : {10000u, 100000u}) {
    const std::vector<Point3> p = pin(n);
    const auto t0 = std::chrono::steady_clock::now();
    const SuperquadricFit fit = fit_superquadric(p);
    std::printf("superquadric %zu points: %.3f s, %d iterations, %s, e1 %.3f e2 %.3f, rms radial %.4f mm\n", n,
                seconds_since(t0), fit.iterations, fit.description.substr(0, fit.description.find(',')).c_str(), fit.model.e1,
                fit.model.e2, fit.rms_radial_mm);
  }
  for (int side : {100, 316}) {
    PointCloud cloud;
    for (int r = 0; r < side; ++r) {
      for (int c = 0; c < side; ++c) {
        const double x = 60.0 * c / (side - 1), y = 60.0 * r / (side - 1);
        cloud.points.push_back({x, y, 5 * std::sin(x / 9) * std::cos(y / 7)});
      }
    }
    const auto t0 = std::chrono::steady_clock::now();
    const Characterization ch = characterize(cloud);
    std::printf("characterize %zu points: %.3f s, %u regions, suggested net %dx%d\n", cloud.points.size(), seconds_since(t0),
                ch.significant_regions, ch.suggested_control_x, ch.suggested_control_y);
  }
  return 0;
}

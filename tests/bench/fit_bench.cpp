// Fitting benchmarks: least-squares B-spline (32 x 32 bicubic) on scattered points, a 1000 x 1000
// grid, the tolerance mode and inspection, on every core, wall time with steady_clock; with
// --write-clouds DIR, the million scattered points as a CSV and a binary PLY instead.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <random>

#include "host/fit/bspline_fit.h"
#include "host/geometry/closest_point.h"
#include "host/geometry/surface_locator.h"
#include "host/inspect/inspect.h"
#include "host/parallel/parallel_for.h"
#include "host/fit/tolerance_fit.h"
#include "host/fit/orthogonal_distances.h"
#include "host/parallel/memory_reuse.h"

using namespace dg::host;

namespace {

double part(double x, double y) {
  return 3.0 + 0.002 * ((x - 50) * (x - 50) + (y - 50) * (y - 50)) + 0.3 * std::sin(x / 9.0) * std::sin(y / 11.0);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

PointCloud make(size_t n, bool grid) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> along(0.0, 100.0);
  std::normal_distribution<double> noise(0.0, 0.002);
  PointCloud c;
  c.points.reserve(n);
  const size_t side = static_cast<size_t>(std::llround(std::sqrt(static_cast<double>(n))));
  for (size_t k = 0; k < n; ++k) {
    const double x = grid ? 100.0 * static_cast<double>(k % side) / static_cast<double>(side - 1) : along(rng);
    const double y = grid ? 100.0 * static_cast<double>(k / side) / static_cast<double>(side - 1) : along(rng);
    c.points.push_back({x, y, part(x, y) + noise(rng)});
  }
  return c;
}

// A figure beside the target it answers to (issue targets on a 2-core machine), with their ratio.
void against_target(const char* what, double seconds, double target_s) {
  std::printf("  target %s <= %.2f s: %.3f s measured, %.2f x the target (%s)\n", what, target_s, seconds, seconds / target_s,
              seconds <= target_s ? "met" : "not met");
}

double lsq(const char* label, const PointCloud& c) {
  const Parameters p = parameterize(c, Parameterization::kTableXy);
  LsqSpec spec;
  spec.knots_u = clamped_uniform_knots(32, 3);
  spec.knots_v = clamped_uniform_knots(32, 3);
  auto t0 = std::chrono::steady_clock::now();
  const BSplineSurface s = fit_least_squares(c.points, p, nullptr, spec);
  const double fit_s = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  const std::vector<double> d = orthogonal_distances(s, c.points, p);
  const double dist_s = seconds_since(t0);
  double worst = 0;
  for (double v : d) worst = std::fmax(worst, std::fabs(v));
  std::printf("%-34s fit %.3f s (%.0f ns/point), orthogonal distances %.3f s, max %.4f mm\n", label, fit_s,
              fit_s * 1e9 / static_cast<double>(c.points.size()), dist_s, worst);
  return fit_s;
}

// The cloud as a CSV and as a binary PLY (points only), for timing the whole fit command on them.
void write_clouds(const PointCloud& c, const std::string& dir) {
  FILE* csv = std::fopen((dir + "/cloud-1e6.csv").c_str(), "w");
  FILE* ply = std::fopen((dir + "/cloud-1e6.ply").c_str(), "wb");
  if (!csv || !ply) {
    std::fprintf(stderr, "fit_bench: cannot write into %s\n", dir.c_str());
    std::exit(1);
  }
  std::fprintf(csv, "x,y,z\n");
  std::fprintf(ply, "ply\nformat binary_little_endian 1.0\nelement vertex %zu\nproperty double x\nproperty double y\n"
               "property double z\nend_header\n", c.points.size());
  for (const Point3& p : c.points) {
    std::fprintf(csv, "%.4f,%.4f,%.5f\n", p.x, p.y, p.z);
    const double xyz[3] = {p.x, p.y, p.z};
    std::fwrite(xyz, sizeof xyz, 1, ply);
  }
  std::fclose(csv);
  std::fclose(ply);
}

}  // namespace

int main(int argc, char** argv) {
  tune_memory(argv, Restart::kAlways);  // huge pages, freed blocks kept (memory_reuse.h)
  const bool quick = argc > 1 && std::string(argv[1]) == "--quick";
  if (argc > 2 && std::string(argv[1]) == "--write-clouds") {
    write_clouds(make(1000000, false), argv[2]);
    return 0;
  }
  lsq("scattered 1e4, 32x32 bicubic", make(10000, false));
  lsq("scattered 1e5, 32x32 bicubic", make(100000, false));
  if (!quick) {
    against_target("for the 1e6-point fit", lsq("scattered 1e6, 32x32 bicubic", make(1000000, false)), 0.15);
    lsq("grid 1000x1000, 32x32 bicubic", make(1000000, true));
  }
  const PointCloud c = make(quick ? 100000 : 1000000, false);
  const Parameters p = parameterize(c, Parameterization::kTableXy);
  ToleranceOptions o;
  o.tolerance_mm = 0.02;
  const auto t0 = std::chrono::steady_clock::now();
  const ToleranceResult r = fit_to_tolerance(c, p, nullptr, o);
  const double tolerance_s = seconds_since(t0);
  std::printf("tolerance 0.02 mm on %zu points: %s, %d x %d control points, %d fits, max %.4f mm, %.3f s "
              "(validated between the samples: %zu points held out, %zu neighbour checks)\n",
              c.points.size(), r.kept ? "kept" : "refused", r.surface.count_u, r.surface.count_v, r.iterations,
              r.max_distance_mm, tolerance_s, r.validation.held_out_points, r.validation.neighbour_checks);
  if (!quick) against_target("for tolerance mode on 1e6 points", tolerance_s, 0.5);
  {
    // Inspection: points with no parameters of their own, against a 32 x 32 bicubic fit.
    LsqSpec spec;
    spec.knots_u = spec.knots_v = clamped_uniform_knots(32, 3);
    const BSplineSurface s = fit_least_squares(c.points, p, nullptr, spec);
    auto t0 = std::chrono::steady_clock::now();
    { const SurfaceLocator setup(s); }
    const double setup_s = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    const Inspection r = inspect(c.points, s, {0.01});
    const double all_s = seconds_since(t0);
    std::printf("inspection of %zu points, 32x32 bicubic, %u threads: %.3f s (%.0f ns/point; the closest-point index's "
                "set-up %.3f s of it), rms %.4f mm, max %.4f mm\n",
                c.points.size(), worker_count(), all_s, all_s * 1e9 / static_cast<double>(c.points.size()), setup_s, r.stats.rms,
                r.stats.max_abs);
    if (!quick) against_target("for inspecting 1e6 points", all_s, 0.5);
  }
  return 0;
}

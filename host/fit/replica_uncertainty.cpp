// Monte Carlo propagation of the points' noise through a fitting method, on all cores.
#include "host/fit/replica_uncertainty.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>
#include <thread>

#include "host/geometry/vec3.h"
#include "host/scan/median.h"

namespace dg::host {

SurfaceUncertainty replica_uncertainty(const std::vector<Point3>& points, const std::vector<double>& sigma_mm,
                                       const BSplineSurface& nominal,
                                       const std::function<BSplineSurface(const std::vector<Point3>&)>& refit,
                                       const ReplicaPlan& plan, int* refused) {
  const int grid = std::max(2, plan.grid), nodes = grid * grid, replicas = std::max(2, plan.replicas);
  // The nominal's points and unit normals at the nodes: each replica's offset along them.
  std::vector<Point3> at(static_cast<size_t>(nodes)), normal(static_cast<size_t>(nodes));
  // A node is a fraction of each surface's own domain: a method whose parameters come from the
  // points (chord lengths) gives each replica a slightly different one.
  auto node_uv = [&](const BSplineSurface& s, int g, double& u, double& v) {
    u = s.u_min() + (s.u_max() - s.u_min()) * (g % grid) / (grid - 1);
    v = s.v_min() + (s.v_max() - s.v_min()) * (g / grid) / (grid - 1);
  };
  for (int g = 0; g < nodes; ++g) {
    double u, v;
    node_uv(nominal, g, u, v);
    Point3 su, sv;
    nominal.evaluate(u, v, at[static_cast<size_t>(g)], su, sv);
    const Point3 n = cross(su, sv);
    const double length = norm(n);
    normal[static_cast<size_t>(g)] = length > 0 ? (1.0 / length) * n : Point3{0, 0, 1};
  }
  // offsets[k * nodes + g]: replica k's offset at node g (NaN for a refused replica).
  std::vector<double> offsets(static_cast<size_t>(replicas) * nodes, std::nan(""));
  std::atomic<int> next{0};
  auto work = [&]() {
    std::vector<Point3> noisy = points;
    for (int k = next++; k < replicas; k = next++) {
      std::mt19937_64 rng(plan.seed * 0x9E3779B97F4A7C15ull + static_cast<unsigned>(k));
      std::normal_distribution<double> unit(0.0, 1.0);
      for (size_t i = 0; i < points.size(); ++i) noisy[i].z = points[i].z + sigma_mm[i] * unit(rng);
      try {
        const BSplineSurface s = refit(noisy);
        for (int g = 0; g < nodes; ++g) {
          double u, v;
          node_uv(s, g, u, v);
          const Point3 d = s.evaluate(u, v) - at[static_cast<size_t>(g)];
          offsets[static_cast<size_t>(k) * nodes + g] = dot(d, normal[static_cast<size_t>(g)]);
        }
      } catch (const std::exception&) {
        // Refused by the method: counted below.
      }
    }
  };
  const unsigned cores = std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
  std::vector<std::thread> threads;
  for (unsigned t = 1; t < cores; ++t) threads.emplace_back(work);
  work();
  for (std::thread& t : threads) t.join();

  int failed = 0;
  for (int k = 0; k < replicas; ++k) failed += std::isnan(offsets[static_cast<size_t>(k) * nodes]) ? 1 : 0;
  if (refused) *refused = failed;
  SurfaceUncertainty out;
  const int used = replicas - failed;
  if (used < 2 || failed * 10 > replicas) return out;
  out.computed = true;
  out.rows = out.cols = grid;
  out.u_mm.assign(static_cast<size_t>(nodes), 0.0);
  out.sigma_mm = median_of(sigma_mm);
  double sum_u = 0;
  for (int g = 0; g < nodes; ++g) {
    double mean = 0;
    for (int k = 0; k < replicas; ++k) {
      const double o = offsets[static_cast<size_t>(k) * nodes + g];
      if (!std::isnan(o)) mean += o;
    }
    mean /= used;
    double ss = 0;
    for (int k = 0; k < replicas; ++k) {
      const double o = offsets[static_cast<size_t>(k) * nodes + g];
      if (!std::isnan(o)) ss += (o - mean) * (o - mean);
    }
    const double u = std::sqrt(ss / (used - 1));
    out.u_mm[static_cast<size_t>(g)] = u;
    out.max_mm = std::max(out.max_mm, u);
    sum_u += u;
  }
  out.mean_mm = sum_u / nodes;
  out.sigma_from = "Monte Carlo over " + std::to_string(used) + " refits of noisy replicas (GUM Supplement 1)";
  return out;
}

}  // namespace dg::host

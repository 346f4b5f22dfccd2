// Characterization as Koivunen and Bajcsy 1992, section 5.3 describes it, with two choices of ours: the type is
// read from the signs of the principal curvatures (each compared with the zero threshold), which
// keeps a cylinder a ridge under noise where a threshold on K itself would not; and the zero
// threshold comes from the noise: a quadratic through a 5 x 5 window of half width w has curvature
// noise of about sigma / w^2, so three times that is taken as zero.
#include "host/fit/characterize.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "host/scan/local_polynomial.h"
#include "host/scan/lts_filter.h"
#include "host/scan/neighbours.h"
#include "host/fit/crease_detect.h"
#include "host/fit/fit_error.h"
#include "host/fit/knot_support.h"
#include "host/fit/noise_estimate.h"
#include "host/fit/parameterize.h"

namespace dg::host {

namespace {

SurfaceType classify(double h, double k, double zero) {
  // Principal curvatures k1 >= k2; a sign is zero within the threshold.
  const double root = std::sqrt(std::max(h * h - k, 0.0));
  const double k1 = h + root, k2 = h - root;
  auto sign = [zero](double v) { return v > zero ? 1 : v < -zero ? -1 : 0; };
  const int sh = sign(h), s1 = sign(k1), s2 = sign(k2);
  const int sk = s1 * s2;
  if (sk > 0) return sh < 0 ? SurfaceType::kPeak : SurfaceType::kPit;
  if (sk < 0) return sh < 0 ? SurfaceType::kSaddleRidge : sh > 0 ? SurfaceType::kSaddleValley : SurfaceType::kMinimal;
  return sh < 0 ? SurfaceType::kRidge : sh > 0 ? SurfaceType::kValley : SurfaceType::kFlat;
}

uint32_t find(std::vector<uint32_t>& parent, uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// The most significant regions met along one row of points (rows: points binned across `along`).
int regions_along(const std::vector<Point3>& p, const std::vector<PointCharacter>& c, const std::vector<bool>& significant,
                  bool along_x, double bin) {
  std::unordered_map<int64_t, std::vector<size_t>> rows;
  for (size_t i = 0; i < p.size(); ++i) rows[static_cast<int64_t>(std::floor((along_x ? p[i].y : p[i].x) / bin))].push_back(i);
  int most = 0;
  for (auto& [key, members] : rows) {
    std::sort(members.begin(), members.end(), [&](size_t a, size_t b) { return along_x ? p[a].x < p[b].x : p[a].y < p[b].y; });
    int count = 0;
    uint32_t last = UINT32_MAX;
    for (size_t i : members) {
      if (!significant[c[i].region] || c[i].region == last) continue;
      last = c[i].region;
      ++count;
    }
    most = std::max(most, count);
  }
  return most;
}

}  // namespace

const char* surface_type_name(SurfaceType type) {
  switch (type) {
    case SurfaceType::kPeak: return "peak";
    case SurfaceType::kRidge: return "ridge";
    case SurfaceType::kSaddleRidge: return "saddle ridge";
    case SurfaceType::kFlat: return "flat";
    case SurfaceType::kMinimal: return "minimal";
    case SurfaceType::kPit: return "pit";
    case SurfaceType::kValley: return "valley";
    case SurfaceType::kSaddleValley: return "saddle valley";
  }
  return "flat";
}

Characterization characterize(const PointCloud& input, const CharacterizeOptions& options) {
  const size_t k = static_cast<size_t>(std::max(options.neighbours, 6));
  if (input.points.size() < k) {
    throw FitError("characterization fits a quadratic to " + std::to_string(k) + " neighbours; there are only " +
                   std::to_string(input.points.size()) + " points");
  }
  PointCloud cloud = input;
  const Parameters params = parameterize(cloud, Parameterization::kTableXy);  // throws for collinear XY
  const double sigma = estimate_noise(cloud, params);
  if (options.robust) {
    const LtsResult filtered = lts_filter(cloud.points, LtsOptions{});
    for (size_t i = 0; i < cloud.points.size(); ++i) cloud.points[i].z = filtered.z[i];
  }
  const std::vector<Point3>& p = cloud.points;
  Characterization out;
  out.points.resize(p.size());
  std::vector<std::vector<size_t>> near;
  nearest_neighbourhoods(p, k, near);
  double radius_sum = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    radius_sum += std::hypot(p[near[i].back()].x - p[i].x, p[near[i].back()].y - p[i].y);
    LocalPolynomial f;
    PointCharacter& c = out.points[i];
    if (!fit_local_polynomial(p, near[i], p[i], 2, f)) {
      c.determined = false;  // a degenerate neighbourhood: no type
      continue;
    }
    // Back from the scaled local coordinates: d/dx = (1 / scale_x) d/d(dx).
    c.fx = f.c[1] / f.scale_x;
    c.fy = f.c[2] / f.scale_y;
    c.fxx = 2 * f.c[3] / (f.scale_x * f.scale_x);
    c.fxy = f.c[4] / (f.scale_x * f.scale_y);
    c.fyy = 2 * f.c[5] / (f.scale_y * f.scale_y);
    const double g = 1 + c.fx * c.fx + c.fy * c.fy;
    c.mean_curvature = ((1 + c.fy * c.fy) * c.fxx - 2 * c.fx * c.fy * c.fxy + (1 + c.fx * c.fx) * c.fyy) / (2 * std::pow(g, 1.5));
    c.gaussian_curvature = (c.fxx * c.fyy - c.fxy * c.fxy) / (g * g);
  }
  const double r = radius_sum / static_cast<double>(p.size());
  // r is the distance to the farthest neighbour, a window's corner: its half width is r / sqrt(2).
  out.zero_curvature = options.zero_curvature > 0 ? options.zero_curvature : std::max(6 * sigma / (r * r), 1e-6);
  for (PointCharacter& c : out.points) {
    if (!c.determined) {
      ++out.undetermined;
      continue;
    }
    c.type = classify(c.mean_curvature, c.gaussian_curvature, out.zero_curvature);
    ++out.type_counts[static_cast<int>(c.type)];
  }
  // Regions: neighbours (the nearest eight) of one type joined.
  std::vector<uint32_t> parent(p.size());
  std::iota(parent.begin(), parent.end(), 0u);
  for (size_t i = 0; i < p.size(); ++i) {
    for (size_t n = 1; n < near[i].size() && n <= 8; ++n) {
      const size_t j = near[i][n];
      if (out.points[i].type != out.points[j].type || !out.points[i].determined || !out.points[j].determined) continue;
      parent[find(parent, static_cast<uint32_t>(i))] = find(parent, static_cast<uint32_t>(j));
    }
  }
  std::unordered_map<uint32_t, uint32_t> ids;
  std::vector<size_t> sizes;
  for (size_t i = 0; i < p.size(); ++i) {
    const uint32_t root = find(parent, static_cast<uint32_t>(i));
    auto [it, added] = ids.emplace(root, static_cast<uint32_t>(ids.size()));
    if (added) sizes.push_back(0);
    out.points[i].region = it->second;
    ++sizes[it->second];
  }
  // An undetermined point is a region of its own, of no type: not counted.
  out.regions = static_cast<uint32_t>(ids.size() - out.undetermined);
  std::vector<bool> significant(sizes.size());
  for (size_t s = 0; s < sizes.size(); ++s) {
    significant[s] = sizes[s] >= options.min_region;
    out.significant_regions += significant[s] ? 1 : 0;
  }
  // Koivunen and Bajcsy 1992: the net follows the most patches met in each direction; a cubic needs three more
  // control points for each patch it crosses.
  const double bin = r / std::sqrt(static_cast<double>(k)) * 1.5;
  out.regions_across_x = regions_along(p, out.points, significant, true, bin);
  out.regions_across_y = regions_along(p, out.points, significant, false, bin);
  // A fit determines at most one control point for each distinct position along a direction
  // (Schoenberg-Whitney): a 50 x 8 grid was offered 22 along its 8 lines.
  const double merge = site_merge_distance(p.size());
  out.distinct_x = distinct_sites(params.uv, true, merge).size();
  out.distinct_y = distinct_sites(params.uv, false, merge).size();
  auto suggested = [](int regions, size_t distinct) {
    if (distinct < 4) return 0;
    return static_cast<int>(std::min<size_t>(distinct, static_cast<size_t>(std::max(4, 3 * regions + 1))));
  };
  out.suggested_control_x = suggested(out.regions_across_x, out.distinct_x);
  out.suggested_control_y = suggested(out.regions_across_y, out.distinct_y);
  const Creases creases = detect_creases(input, params, sigma);
  for (double u : creases.u) out.creases_x_mm.push_back(params.x_min + u * (params.x_max - params.x_min));
  for (double v : creases.v) out.creases_y_mm.push_back(params.y_min + v * (params.y_max - params.y_min));
  return out;
}

}  // namespace dg::host

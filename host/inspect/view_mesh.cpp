// Cropping a mesh to the measured area and coarsening it by vertex clustering.
#include "host/inspect/view_mesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>

namespace dg::host {

namespace {

// Vertices merged in cubic cells of `cell_mm`: each cell's vertices become their mean, and a
// triangle whose corners fall in fewer than three cells is dropped, as is a repeat of one kept.
Mesh clustered(const Mesh& in, double cell_mm) {
  using Key = std::tuple<long, long, long>;
  std::map<Key, uint32_t> cell_of_key;
  std::vector<uint32_t> cell_of_vertex(in.vertices.size());
  std::vector<Point3> sum;
  std::vector<double> count;
  for (size_t v = 0; v < in.vertices.size(); ++v) {
    const Point3& p = in.vertices[v];
    const Key key{std::lround(std::floor(p.x / cell_mm)), std::lround(std::floor(p.y / cell_mm)), std::lround(std::floor(p.z / cell_mm))};
    const auto found = cell_of_key.emplace(key, static_cast<uint32_t>(sum.size()));
    if (found.second) sum.push_back({0, 0, 0}), count.push_back(0);
    const uint32_t c = found.first->second;
    cell_of_vertex[v] = c;
    sum[c].x += p.x, sum[c].y += p.y, sum[c].z += p.z;
    count[c] += 1;
  }
  Mesh out;
  for (size_t c = 0; c < sum.size(); ++c) out.vertices.push_back({sum[c].x / count[c], sum[c].y / count[c], sum[c].z / count[c]});
  std::set<std::array<uint32_t, 3>> seen;
  for (const auto& t : in.triangles) {
    const std::array<uint32_t, 3> corners = {cell_of_vertex[t[0]], cell_of_vertex[t[1]], cell_of_vertex[t[2]]};
    if (corners[0] == corners[1] || corners[1] == corners[2] || corners[0] == corners[2]) continue;
    std::array<uint32_t, 3> sorted = corners;
    std::sort(sorted.begin(), sorted.end());
    if (seen.insert(sorted).second) out.triangles.push_back(corners);
  }
  return out;
}

struct Box {
  double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
};

// The measured points' extent in XY.
Box points_box(const Inspection& inspection) {
  Box b;
  for (const PointDeviation& d : inspection.points) {
    b.x0 = std::min(b.x0, d.point.x), b.x1 = std::max(b.x1, d.point.x), b.y0 = std::min(b.y0, d.point.y), b.y1 = std::max(b.y1, d.point.y);
  }
  return b;
}

}  // namespace

Mesh mesh_for_view(const Mesh& mesh, const Inspection& inspection, size_t max_triangles) {
  Mesh out;
  if (inspection.points.empty() || mesh.triangles.empty() || max_triangles == 0) return out;
  Box b = points_box(inspection);
  const double margin = 0.1 * std::max(b.x1 - b.x0, b.y1 - b.y0);
  b.x0 -= margin, b.x1 += margin, b.y0 -= margin, b.y1 += margin;
  auto inside = [&](const Point3& p) { return p.x >= b.x0 && p.x <= b.x1 && p.y >= b.y0 && p.y <= b.y1; };
  // The triangles near the points, with their vertices renumbered.
  std::vector<uint32_t> renumbered(mesh.vertices.size(), UINT32_MAX);
  for (const auto& t : mesh.triangles) {
    if (!inside(mesh.vertices[t[0]]) && !inside(mesh.vertices[t[1]]) && !inside(mesh.vertices[t[2]])) continue;
    std::array<uint32_t, 3> corners{};
    for (int k = 0; k < 3; ++k) {
      uint32_t& to = renumbered[t[k]];
      if (to == UINT32_MAX) to = static_cast<uint32_t>(out.vertices.size()), out.vertices.push_back(mesh.vertices[t[k]]);
      corners[k] = to;
    }
    out.triangles.push_back(corners);
  }
  // A grid of about max_triangles / 2 cells over the area to start with, a third coarser each time.
  double cell = std::hypot(b.x1 - b.x0, b.y1 - b.y0) / std::sqrt(static_cast<double>(max_triangles) / 2);
  for (int round = 0; out.triangles.size() > max_triangles && round < 60; ++round, cell *= 1.5) out = clustered(out, cell);
  if (out.triangles.size() > max_triangles) out = Mesh{};
  return out;
}

Mesh fitted_surface_for_view(const FittedSurface& surface, const Inspection& inspection) {
  const Box b = points_box(inspection);
  const double extent = std::hypot(b.x1 - b.x0, b.y1 - b.y0);
  if (!(extent > 0)) return Mesh{};
  const double chord = std::max(0.002, 1e-3 * extent);
  constexpr size_t kLargest = 400000;  // meshed finer than this, the surface is coarsened by mesh_for_view anyway
  try {
    if (!surface.faces.empty()) return mesh_for_view(tessellate_faces(surface.faces, chord, extent / 100, kLargest), inspection);
    if (surface.surface.count_u > 0 && surface.surface.count_v > 0) {
      return mesh_for_view(tessellate(surface.surface, chord, kLargest), inspection);
    }
  } catch (const std::invalid_argument&) {
    // Too fine to mesh within the limit: the view shows the points alone.
  }
  return Mesh{};
}

}  // namespace dg::host

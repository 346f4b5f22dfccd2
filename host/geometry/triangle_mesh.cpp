// Closest points on triangle meshes: the triangle's Voronoi regions, a median-split box tree, and
// angle-weighted pseudo-normals for the distance's sign.
#include "host/geometry/triangle_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "host/geometry/vec3.h"

namespace dg::host {

namespace {

constexpr uint32_t kLeafTriangles = 4;

Point3 unit(Point3 v) {
  const double n = norm(v);
  return n > 0 ? (1.0 / n) * v : Point3{};
}

// The squared distance from p to a box (0 inside it).
double box_distance2(const Point3& p, const Point3& low, const Point3& high) {
  auto axis = [](double v, double lo, double hi) { return v < lo ? lo - v : v > hi ? v - hi : 0.0; };
  const double dx = axis(p.x, low.x, high.x), dy = axis(p.y, low.y, high.y), dz = axis(p.z, low.z, high.z);
  return dx * dx + dy * dy + dz * dz;
}

}  // namespace

Point3 closest_on_triangle(const Point3& p, const Point3& a, const Point3& b, const Point3& c, int* feature) {
  const Point3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return *feature = 4, a;
  const Point3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return *feature = 5, b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return *feature = 1, a + (d1 / (d1 - d3)) * ab;
  const Point3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return *feature = 6, c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return *feature = 3, a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return *feature = 2, b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  const double denominator = 1.0 / (va + vb + vc);
  *feature = 0;
  return a + (vb * denominator) * ab + (vc * denominator) * ac;
}

MeshLocator::MeshLocator(Mesh mesh) : mesh_(std::move(mesh)) {
  if (mesh_.triangles.empty()) throw std::invalid_argument("the mesh has no triangles");
  const size_t n = mesh_.vertices.size();
  for (size_t v = 0; v < n; ++v) {
    const Point3& q = mesh_.vertices[v];
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) {
      throw std::invalid_argument("vertex " + std::to_string(v + 1) + " of the mesh has a coordinate that is not a finite number");
    }
  }
  face_normal_.resize(mesh_.triangles.size());
  vertex_normal_.assign(n, Point3{});
  edge_normal_.resize(mesh_.triangles.size());
  // Undirected edge -> the sum of its faces' normals, and how many faces with area it has.
  struct EdgeFaces {
    Point3 normal_sum;
    int faces = 0;
  };
  std::map<std::pair<uint32_t, uint32_t>, EdgeFaces> edges;
  for (size_t t = 0; t < mesh_.triangles.size(); ++t) {
    const auto& tri = mesh_.triangles[t];
    for (uint32_t index : tri) {
      if (index >= n) {
        throw std::invalid_argument("triangle " + std::to_string(t + 1) + " of the mesh names vertex " + std::to_string(index + 1) +
                                    " of " + std::to_string(n));
      }
    }
    const Point3 a = mesh_.vertices[tri[0]], b = mesh_.vertices[tri[1]], c = mesh_.vertices[tri[2]];
    const Point3 normal = cross(b - a, c - a);
    // A triangle without area (corners on one line) has no side, and its points lie on its
    // neighbours' edges: it is left out of the search, and counted.
    if (!(norm(normal) > 0)) {
      ++without_area_;
      continue;
    }
    face_normal_[t] = unit(normal);
    // Each corner's angle weights the face's normal at that vertex (Baerentzen and Aanaes 2005).
    const Point3 corner[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const Point3 e1 = unit(corner[(k + 1) % 3] - corner[k]), e2 = unit(corner[(k + 2) % 3] - corner[k]);
      const double angle = std::acos(std::clamp(dot(e1, e2), -1.0, 1.0));
      vertex_normal_[tri[static_cast<size_t>(k)]] += angle * face_normal_[t];
      const uint32_t u = tri[static_cast<size_t>(k)], w = tri[static_cast<size_t>((k + 1) % 3)];
      EdgeFaces& edge = edges[{std::min(u, w), std::max(u, w)}];
      edge.normal_sum += face_normal_[t];
      ++edge.faces;
    }
  }
  edge_open_.assign(mesh_.triangles.size(), {false, false, false});
  vertex_open_.assign(n, 0);
  for (size_t t = 0; t < mesh_.triangles.size(); ++t) {
    const auto& tri = mesh_.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const uint32_t u = tri[static_cast<size_t>(k)], w = tri[static_cast<size_t>((k + 1) % 3)];
      const EdgeFaces& edge = edges[{std::min(u, w), std::max(u, w)}];
      edge_normal_[t][static_cast<size_t>(k)] = edge.normal_sum;
      // An edge of one triangle is the border of an open mesh (a single face of a part, a scan's
      // mesh); a closed solid's every edge has two.
      if (norm(face_normal_[t]) > 0 && edge.faces == 1) {
        edge_open_[t][static_cast<size_t>(k)] = true;
        vertex_open_[u] = vertex_open_[w] = 1;
      }
    }
  }
  for (size_t t = 0; t < mesh_.triangles.size(); ++t) {
    if (norm(face_normal_[t]) > 0) order_.push_back(static_cast<uint32_t>(t));
  }
  if (order_.empty()) throw std::invalid_argument("the mesh has no triangle with area");
  nodes_.reserve(2 * order_.size() / kLeafTriangles + 2);
  build(0, static_cast<uint32_t>(order_.size()));
}

uint32_t MeshLocator::build(uint32_t first, uint32_t count) {
  const uint32_t index = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back(Node{});
  Node node;
  node.low = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
  node.high = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (uint32_t k = first; k < first + count; ++k) {
    for (uint32_t v : mesh_.triangles[order_[k]]) {
      const Point3& q = mesh_.vertices[v];
      node.low = {std::min(node.low.x, q.x), std::min(node.low.y, q.y), std::min(node.low.z, q.z)};
      node.high = {std::max(node.high.x, q.x), std::max(node.high.y, q.y), std::max(node.high.z, q.z)};
    }
  }
  if (count <= kLeafTriangles) {
    node.first = first;
    node.count = count;
    nodes_[index] = node;
    return index;
  }
  // Split at the median of the triangles' centroids along the box's longest axis.
  const Point3 size = node.high - node.low;
  const int axis = size.x >= size.y && size.x >= size.z ? 0 : size.y >= size.z ? 1 : 2;
  auto centre = [&](uint32_t t) {
    const auto& tri = mesh_.triangles[t];
    const Point3 s = mesh_.vertices[tri[0]] + mesh_.vertices[tri[1]] + mesh_.vertices[tri[2]];
    return axis == 0 ? s.x : axis == 1 ? s.y : s.z;
  };
  const uint32_t half = count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                   [&](uint32_t l, uint32_t r) { return centre(l) < centre(r); });
  node.left = build(first, half);
  node.right = build(first + half, count - half);
  nodes_[index] = node;
  return index;
}

Point3 MeshLocator::feature_normal(size_t triangle, int feature) const {
  if (feature == 0) return face_normal_[triangle];
  if (feature <= 3) return edge_normal_[triangle][static_cast<size_t>(feature - 1)];
  return vertex_normal_[mesh_.triangles[triangle][static_cast<size_t>(feature - 4)]];
}

bool MeshLocator::on_border(size_t triangle, int feature) const {
  if (feature == 0) return false;
  // Edges 1..3 are ab, bc, ca: edge k + 1 starts at corner k, as edge_open_ counts them.
  if (feature <= 3) return edge_open_[triangle][static_cast<size_t>(feature - 1)];
  return vertex_open_[mesh_.triangles[triangle][static_cast<size_t>(feature - 4)]] != 0;
}

Closest MeshLocator::closest(const Point3& p, size_t* triangle) const {
  double best2 = HUGE_VAL;
  Point3 best_point;
  size_t best_triangle = 0;
  int best_feature = 0;
  // Depth first, the nearer child first, skipping boxes farther than the best so far.
  uint32_t stack[128];
  int depth = 0;
  stack[depth++] = 0;
  while (depth > 0) {
    const Node& node = nodes_[stack[--depth]];
    if (box_distance2(p, node.low, node.high) >= best2) continue;
    if (node.count > 0) {
      for (uint32_t k = node.first; k < node.first + node.count; ++k) {
        const auto& tri = mesh_.triangles[order_[k]];
        int feature = 0;
        const Point3 q = closest_on_triangle(p, mesh_.vertices[tri[0]], mesh_.vertices[tri[1]], mesh_.vertices[tri[2]], &feature);
        const Point3 d = p - q;
        const double d2 = dot(d, d);
        if (d2 < best2) best2 = d2, best_point = q, best_triangle = order_[k], best_feature = feature;
      }
      continue;
    }
    const double left = box_distance2(p, nodes_[node.left].low, nodes_[node.left].high);
    const double right = box_distance2(p, nodes_[node.right].low, nodes_[node.right].high);
    // 128 levels hold any tree of median splits over 2^32 triangles.
    if (left < right) {
      stack[depth++] = node.right, stack[depth++] = node.left;
    } else {
      stack[depth++] = node.left, stack[depth++] = node.right;
    }
  }
  Closest out;
  out.point = best_point;
  const double distance = std::sqrt(best2);
  const Point3 normal = feature_normal(best_triangle, best_feature);
  out.distance = dot(p - best_point, normal) < 0 ? -distance : distance;
  out.normal = unit(normal);
  out.on_border = on_border(best_triangle, best_feature);
  if (triangle) *triangle = best_triangle;
  return out;
}

void MeshLocator::triangles_within(const Point3& p, double radius_mm, std::vector<size_t>& out) const {
  out.clear();
  const double radius2 = radius_mm * radius_mm;
  uint32_t stack[128];
  int depth = 0;
  stack[depth++] = 0;
  while (depth > 0) {
    const Node& node = nodes_[stack[--depth]];
    if (box_distance2(p, node.low, node.high) > radius2) continue;
    if (node.count == 0) {
      stack[depth++] = node.left, stack[depth++] = node.right;
      continue;
    }
    for (uint32_t k = node.first; k < node.first + node.count; ++k) {
      const auto& tri = mesh_.triangles[order_[k]];
      int feature = 0;
      const Point3 d = p - closest_on_triangle(p, mesh_.vertices[tri[0]], mesh_.vertices[tri[1]], mesh_.vertices[tri[2]], &feature);
      if (dot(d, d) <= radius2) out.push_back(order_[k]);
    }
  }
}

}  // namespace dg::host

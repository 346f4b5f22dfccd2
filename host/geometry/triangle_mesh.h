// The closest point on a triangle mesh (a user's STL or OBJ as a nominal), with a signed distance.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "host/geometry/closest_point.h"
#include "host/geometry/point3.h"
#include "host/geometry/tessellate.h"

namespace dg::host {

// The point on a triangle nearest to p (Voronoi regions of the vertices, edges and face, after
// Ericson 2005, section 5.1.5); `feature` is 0 for the face, 1..3 for the edges ab, bc, ca and
// 4..6 for the vertices a, b, c.
Point3 closest_on_triangle(const Point3& p, const Point3& a, const Point3& b, const Point3& c, int* feature);

// Closest points on a mesh through a bounding-volume tree of its triangles (boxes split at the
// median of the longest axis). The distance's sign comes from the angle-weighted pseudo-normal of
// the nearest feature (Baerentzen and Aanaes 2005), which gives the right side at edges and
// corners where a face normal alone does not: positive on the side the triangles face (above an
// upward-facing height field, as for a surface's S_u x S_v). u and v of the result are 0.
class MeshLocator {
 public:
  // Throws std::invalid_argument for no triangles, an index out of range or a coordinate that is
  // not finite (naming it).
  // Takes the mesh by value: a caller done with its mesh moves it in instead of keeping two copies.
  explicit MeshLocator(Mesh mesh);
  // `triangle`, when given, receives the nearest triangle's index in the mesh.
  Closest closest(const Point3& p, size_t* triangle = nullptr) const;
  // Every triangle (index into the mesh) that comes within `radius_mm` of p, in no order.
  void triangles_within(const Point3& p, double radius_mm, std::vector<size_t>& out) const;
  size_t triangle_count() const { return mesh_.triangles.size(); }
  const std::array<uint32_t, 3>& triangle(size_t t) const { return mesh_.triangles[t]; }
  const Point3& vertex(size_t v) const { return mesh_.vertices[v]; }
  size_t without_area() const { return without_area_; }  // triangles whose corners lie on one line
  const Mesh& mesh() const { return mesh_; }

 private:
  struct Node {
    Point3 low, high;
    uint32_t first = 0, count = 0;  // a leaf's triangles in order_[first, first + count)
    uint32_t left = 0, right = 0;   // an inner node's children (count == 0)
  };
  uint32_t build(uint32_t first, uint32_t count);
  Point3 feature_normal(size_t triangle, int feature) const;

  Mesh mesh_;
  std::vector<Node> nodes_;
  std::vector<uint32_t> order_;
  std::vector<Point3> face_normal_, vertex_normal_;  // unit; vertices' angle-weighted
  std::vector<std::array<Point3, 3>> edge_normal_;  // per triangle edge: the sum of its faces' normals
  // Per triangle edge, and per vertex: on the mesh's border (an edge of one triangle with area).
  std::vector<std::array<bool, 3>> edge_open_;
  std::vector<char> vertex_open_;
  bool on_border(size_t triangle, int feature) const;
  size_t without_area_ = 0;
};

}  // namespace dg::host

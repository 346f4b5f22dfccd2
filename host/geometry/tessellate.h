// Triangles for a surface to a chord tolerance: what STL, OBJ and PLY meshes carry.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "host/geometry/bspline_surface.h"
#include "host/geometry/trimmed_face.h"

namespace dg::host {

struct Mesh {
  std::vector<Point3> vertices;               // mm
  std::vector<std::array<uint32_t, 3>> triangles;  // counter-clockwise seen from S_u x S_v
  double chord_error_mm = 0;                  // the largest deviation found at the check points
};

// The most triangles a mesh may have unless the caller says otherwise (about 1 GB of STL).
constexpr size_t kMaxMeshTriangles = 20000000;

// Distance from p to the triangle a-b-c (mm).
double distance_to_triangle(const Point3& p, const Point3& a, const Point3& b, const Point3& c);

// A tensor grid in (u, v) whose strips are halved where they err (so lines gather where the
// surface bends) until the surface is within `chord_mm` of the triangles at every cell's centre
// and edge midpoints (and the knots are grid lines, so creases stay sharp). Throws
// std::invalid_argument for chord_mm <= 0 or a grid that would exceed max_triangles.
// With angle_deg > 0 a cell is also split until both its triangles' normals lie within that angle
// of the surface's normal at its centre.
Mesh tessellate(const BSplineSurface& surface, double chord_mm, size_t max_triangles = kMaxMeshTriangles, double angle_deg = 0);

// Trimmed faces in one mesh: each face's surface on a uniform grid no coarser than `cell_mm` in XY,
// halved until within `chord_mm` at the cells' centres, cut at the face's loops (face_mesh.h): the
// mesh ends on the trims, and two faces that share a boundary share its vertices' XY.
Mesh tessellate_faces(const std::vector<TrimmedFace>& faces, double chord_mm, double cell_mm,
                      size_t max_triangles = kMaxMeshTriangles);

}  // namespace dg::host

// Reading triangle meshes users have (STL, binary or ASCII, and Wavefront OBJ) as nominals to inspect against.
#pragma once
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "host/geometry/tessellate.h"

namespace dg::host {

class MeshFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// STL: binary when the size is exactly 84 bytes plus 50 per counted triangle (whatever the header
// says; many binary files start with "solid"), else ASCII `facet ... outer loop, vertex x y z (3),
// endloop endfacet`. Corners at the same coordinates become one vertex, so the mesh's edges and
// corners are shared as the file's author meant. The file's normals are ignored: the corners'
// order gives the side, as the format prescribes. Coordinates are taken as millimetres.
Mesh parse_stl(const uint8_t* data, size_t size, const std::string& name);

// OBJ: `v x y z [w]` and `f` lines (indices 1-based or negative, `i`, `i/t`, `i//n` or `i/t/n`);
// a polygon of more than three corners is split into a fan. Other statements (vt, vn, g, o, s,
// usemtl, mtllib, l) are read past. Millimetres.
Mesh parse_obj(const std::string& text, const std::string& name);

// By extension (.stl, .obj). Every error names the file and the triangle, vertex or line: a short
// or overlong binary body, text that is not a number, an index out of range, a coordinate that
// is not finite, no triangles at all.
Mesh read_mesh(const std::string& path);

}  // namespace dg::host

// Triangle meshes of a surface as files: binary STL, OBJ and binary PLY, in millimetres.
#pragma once
#include <string>

#include "host/geometry/tessellate.h"

namespace dg::host {

// Binary STL: 80-byte header, triangle count, per triangle its unit normal, three vertices and a
// zero attribute, all little-endian float32.
std::string stl_bytes(const Mesh& mesh);
// Wavefront OBJ: `v x y z` lines and 1-based `f a b c` lines, with a comment naming the units.
std::string obj_text(const Mesh& mesh);
// Binary little-endian PLY: float x, y, z vertices and uchar-counted int faces.
std::string ply_mesh_bytes(const Mesh& mesh);
// Picks the format from the extension (.stl, .obj, .ply); throws std::invalid_argument otherwise.
void write_mesh(const std::string& path, const Mesh& mesh);

}  // namespace dg::host

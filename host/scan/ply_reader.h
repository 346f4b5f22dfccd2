// PLY point clouds, ASCII or binary: the reader behind read_points for .ply files.
#pragma once
#include <cstddef>
#include <array>
#include <cstdint>
#include <vector>
#include <string>

#include "host/scan/point_reader.h"

namespace dg::host {

// Reads the vertex element's x, y, z (mm) and, when all present, nx, ny, nz; skips other elements
// (faces, edges). Throws PointFileError naming the file and the text line or vertex number for a
// damaged header, a short body, a non-finite value, an unknown vertex property or a repeated point.
PointCloud parse_ply_points(const uint8_t* data, size_t size, const std::string& name);

// A PLY mesh: the vertices as above and the face element's `vertex_indices` (or `vertex_index`)
// lists, each polygon split into a fan of triangles. Repeated vertices are allowed here (a mesh
// may share nothing); an index beyond the vertices, or no face element, is an error naming the face.
PointCloud parse_ply_mesh(const uint8_t* data, size_t size, const std::string& name,
                          std::vector<std::array<uint32_t, 3>>& triangles);

}  // namespace dg::host

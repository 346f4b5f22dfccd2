// Corners at one position become one vertex: meshes read per triangle (STL) or per face (a CAD
// part's faces) share their edges again, so pseudo-normals see across them.
#pragma once
#include <cstdint>
#include <map>
#include <tuple>

#include "host/geometry/tessellate.h"

namespace dg::host {

// Adds vertices to `mesh`, one per distinct position (exactly equal coordinates), in order of first appearance.
class VertexWelder {
 public:
  explicit VertexWelder(Mesh& mesh) : mesh_(mesh) {}
  uint32_t add(const Point3& p) {
    const auto [it, fresh] = index_.emplace(std::make_tuple(p.x, p.y, p.z), static_cast<uint32_t>(mesh_.vertices.size()));
    if (fresh) mesh_.vertices.push_back(p);
    return it->second;
  }

 private:
  Mesh& mesh_;
  std::map<std::tuple<double, double, double>, uint32_t> index_;
};

}  // namespace dg::host

// A height field, or a simulated part's true shape, as a nominal mesh over a rectangle, for tests
// that align or inspect against a mesh (an open one: its border is the rectangle's).
#pragma once
#include <cmath>
#include <cstdint>

#include "host/geometry/tessellate.h"
#include "hw/sim/parts.h"

namespace dg::test {

// The surface z = height(x, y) over [x0, x1] x [y0, y1] at vertices every `step_mm`, two triangles
// a cell (counter-clockwise seen from above).
template <class Height>
host::Mesh height_mesh(Height height, double x0, double x1, double y0, double y1, double step_mm) {
  host::Mesh mesh;
  const int nx = static_cast<int>(std::lround((x1 - x0) / step_mm)), ny = static_cast<int>(std::lround((y1 - y0) / step_mm));
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const double x = x0 + step_mm * i, y = y0 + step_mm * j;
      mesh.vertices.push_back({x, y, height(x, y)});
    }
  auto at = [&](int i, int j) { return static_cast<uint32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return mesh;
}

// The simulated part `kind`'s true shape so meshed.
inline host::Mesh part_mesh(sim::PartKind kind, double x0, double x1, double y0, double y1, double step_mm = 0.2) {
  return height_mesh([kind](double x, double y) { return sim::shape_height_mm(kind, x, y); }, x0, x1, y0, y1, step_mm);
}

}  // namespace dg::test

// The simulated part's exact shape as a nominal mesh, standing in for the drawing a user's CAD
// program would export: the demo inspects a scanned part against it instead of against a surface
// fitted to the scan. Usage: part-nominal PART X0:X1 Y0:Y1 STEP_MM OUT.(stl|obj|ply)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "host/cad/mesh_writer.h"
#include "hw/sim/parts.h"

namespace {

bool parse_range(const char* text, double& lo, double& hi) {
  char* end = nullptr;
  lo = std::strtod(text, &end);
  if (*end != ':') return false;
  hi = std::strtod(end + 1, &end);
  return *end == '\0' && std::isfinite(lo) && std::isfinite(hi) && hi > lo;
}

}  // namespace

int main(int argc, char** argv) {
  dg::sim::PartKind kind;
  double x0, x1, y0, y1;
  const double step = argc == 6 ? std::strtod(argv[4], nullptr) : 0;
  if (argc != 6 || !dg::sim::parse_part(argv[1], &kind) || !parse_range(argv[2], x0, x1) || !parse_range(argv[3], y0, y1) ||
      !(step > 0)) {
    std::fprintf(stderr, "usage: part-nominal dome|saddle|canister|flat X0:X1 Y0:Y1 STEP_MM OUT.(stl|obj|ply)\n");
    return 2;
  }
  const int nx = static_cast<int>(std::ceil((x1 - x0) / step)) + 1, ny = static_cast<int>(std::ceil((y1 - y0) / step)) + 1;
  if (static_cast<double>(nx) * ny > 2e7) {
    std::fprintf(stderr, "part-nominal: %d x %d vertices is too many; take a larger step\n", nx, ny);
    return 2;
  }
  dg::host::Mesh mesh;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double x = std::fmin(x0 + i * step, x1), y = std::fmin(y0 + j * step, y1);
      mesh.vertices.push_back({x, y, dg::sim::shape_height_mm(kind, x, y)});
    }
  }
  // Two triangles per cell, counter-clockwise seen from above: the side the gauge touches. At each
  // cell's centre (on the shared diagonal) the true shape is compared with the mesh, which gives
  // the mesh's own error as a nominal.
  double chord_mm = 0;
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      const uint32_t v = static_cast<uint32_t>(j * nx + i), w = v + static_cast<uint32_t>(nx);
      mesh.triangles.push_back({v, v + 1, w + 1});
      mesh.triangles.push_back({v, w + 1, w});
      const dg::host::Point3 a = mesh.vertices[v], c = mesh.vertices[w + 1];
      const double mid = dg::sim::shape_height_mm(kind, 0.5 * (a.x + c.x), 0.5 * (a.y + c.y));
      chord_mm = std::fmax(chord_mm, std::fabs(mid - 0.5 * (a.z + c.z)));
    }
  }
  try {
    dg::host::write_mesh(argv[5], mesh);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "part-nominal: %s\n", e.what());
    return 1;
  }
  std::printf("wrote the %s's exact shape over x %g..%g, y %g..%g mm at %g mm (%zu triangles, %.4f mm from the shape at the "
              "cells' centres) to %s\n",
              argv[1], x0, x1, y0, y1, step, mesh.triangles.size(), chord_mm, argv[5]);
  return 0;
}

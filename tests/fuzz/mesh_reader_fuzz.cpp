// Fuzzes the STL, OBJ and PLY mesh readers and the mesh locator behind a mesh nominal: damaged files give
// MeshFileError (or the locator's invalid_argument), never a crash; a mesh read whole measures a
// point to a finite distance.
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "host/cad/mesh_reader.h"
#include "host/geometry/triangle_mesh.h"
#include "host/scan/ply_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  for (int format = 0; format < 3; ++format) {
    try {
      dg::host::Mesh mesh;
      if (format == 0) mesh = dg::host::parse_stl(data, size, "fuzz.stl");
      if (format == 1) mesh = dg::host::parse_obj(std::string(reinterpret_cast<const char*>(data), size), "fuzz.obj");
      if (format == 2) mesh.vertices = dg::host::parse_ply_mesh(data, size, "fuzz.ply", mesh.triangles).points;
      const dg::host::MeshLocator locator(mesh);
      const dg::host::Closest c = locator.closest({0.5, 0.5, 0.5});
      // Vertices beyond 1e154 mm square to infinity: such a file is no part, but must not crash.
      if (std::isnan(c.distance)) {
        bool huge = false;
        for (const dg::host::Point3& v : mesh.vertices) huge = huge || std::fabs(v.x) + std::fabs(v.y) + std::fabs(v.z) > 1e150;
        if (!huge) std::abort();
      }
    } catch (const dg::host::MeshFileError&) {
    } catch (const dg::host::PointFileError&) {
    } catch (const std::invalid_argument&) {
    }
  }
  return 0;
}

// Measuring against nominals: a 40 x 30 x 5 mm plate with 24 round bosses (54 faces: planes and
// cylinders), built by OpenCASCADE and written as STEP and as a 1e5-triangle STL, read back as
// nominals; 1e6 points 0.01 mm above its top faces. Prints the time per point for each.
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <StlAPI_Writer.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Writer.hxx>
#include <gp_Ax2.hxx>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <unistd.h>

#include "host/cad/cad_nominal.h"
#include "host/cad/mesh_reader.h"
#include "host/geometry/triangle_mesh.h"

namespace {

// Measures a 1000 x 1000 raster (0.04 x 0.03 mm) 0.01 mm above the part's top (z 5 on the plate, 7 on
// a boss) and prints the time per point and the worst error away from the bosses' walls.
template <typename Closest>
void measure(const char* what, double read_s, const Closest& closest) {
  const auto start = std::chrono::steady_clock::now();
  size_t points = 0;
  double worst = 0;
  for (int j = 0; j < 1000; ++j) {
    for (int i = 0; i < 1000; ++i, ++points) {
      const double x = 0.02 + 0.04 * i, y = 0.015 + 0.03 * j;
      double to_axis = 1e9;
      for (int a = 0; a < 6; ++a)
        for (int b = 0; b < 4; ++b) to_axis = std::fmin(to_axis, std::hypot(x - (5 + 6 * a), y - (5 + 6.5 * b)));
      const double top = to_axis < 1.5 ? 7 : 5;
      const double distance = closest({x, y, top + 0.01});
      // The true distance is 0.01 mm except within 0.05 mm of a boss's wall (left out of the check).
      if (std::fabs(to_axis - 1.5) >= 0.05) worst = std::fmax(worst, std::fabs(distance - 0.01));
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("  %-34s read in %.2f s; %zu points in %.2f s (%.1f us a point), worst |distance - 0.01| %.2g mm\n", what,
              read_s, points, seconds, 1e6 * seconds / static_cast<double>(points), worst);
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main() {
  using Clock = std::chrono::steady_clock;
  TopoDS_Shape part = BRepPrimAPI_MakeBox(40, 30, 5).Shape();
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 4; ++j) {
      const gp_Ax2 axis(gp_Pnt(5 + 6 * i, 5 + 6.5 * j, 5), gp_Dir(0, 0, 1));
      part = BRepAlgoAPI_Fuse(part, BRepPrimAPI_MakeCylinder(axis, 1.5, 2).Shape()).Shape();
    }
  }
  const std::string base = std::string(P_tmpdir) + "/dg_nominal_bench_" + std::to_string(getpid());
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));  // its report is no result
  STEPControl_Writer writer;
  writer.Transfer(part, STEPControl_AsIs);
  writer.Write((base + ".stp").c_str());
  // The same part as an STL of about 1e5 triangles, the size of a scanned or exported mesh nominal.
  BRepMesh_IncrementalMesh(part, 0.0002, false, 0.012, false);
  StlAPI_Writer().Write(part, (base + ".stl").c_str());

  std::printf("1e6 points 0.01 mm above a 40 x 30 mm plate with 24 round bosses, against the part as a nominal:\n");
  auto start = Clock::now();
  const std::unique_ptr<dg::host::CadNominal> nominal = dg::host::CadNominal::read(base + ".stp");
  double read_s = seconds_since(start);
  char what[96];
  std::snprintf(what, sizeof what, "STEP, %zu faces (exact, OpenCASCADE):", nominal->face_count());
  measure(what, read_s, [&](const dg::host::Point3& p) { return nominal->closest(p).distance; });
  std::printf("  %zu of them measured on the CAD part's mesh instead (the exact search failed)\n",
              nominal->mesh_fallbacks());

  start = Clock::now();
  const dg::host::MeshLocator mesh(dg::host::read_mesh(base + ".stl"));
  read_s = seconds_since(start);
  std::snprintf(what, sizeof what, "STL, %zu triangles:", mesh.triangle_count());
  measure(what, read_s, [&](const dg::host::Point3& p) { return mesh.closest(p).distance; });
  std::remove((base + ".stp").c_str());
  std::remove((base + ".stl").c_str());
  return 0;
}

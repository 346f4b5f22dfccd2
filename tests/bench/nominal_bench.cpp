// Measuring against CAD nominals: a 40 x 30 x 5 mm plate with 24 round bosses (54 faces: planes and
// cylinders), built and written as STEP by OpenCASCADE, read back as a nominal; points 0.01 mm
// above its top faces (plate and bosses). Prints the time per point for the exact measurement.
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Writer.hxx>
#include <gp_Ax2.hxx>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <unistd.h>

#include "host/cad/cad_nominal.h"

int main() {
  using Clock = std::chrono::steady_clock;
  TopoDS_Shape part = BRepPrimAPI_MakeBox(40, 30, 5).Shape();
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 4; ++j) {
      const gp_Ax2 axis(gp_Pnt(5 + 6 * i, 5 + 6.5 * j, 5), gp_Dir(0, 0, 1));
      part = BRepAlgoAPI_Fuse(part, BRepPrimAPI_MakeCylinder(axis, 1.5, 2).Shape()).Shape();
    }
  }
  const std::string path = std::string(P_tmpdir) + "/dg_nominal_bench_" + std::to_string(getpid()) + ".stp";
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));  // its report is no result
  STEPControl_Writer writer;
  writer.Transfer(part, STEPControl_AsIs);
  writer.Write(path.c_str());
  auto start = Clock::now();
  const dg::host::CadNominal nominal = dg::host::CadNominal::read(path);
  const double read_s = std::chrono::duration<double>(Clock::now() - start).count();
  // 100,000 points on a 0.1 mm raster 0.01 mm above the part's top (z 5 on the plate, 7 on a boss).
  start = Clock::now();
  size_t points = 0;
  double worst = 0;
  for (int j = 0; j < 250; ++j) {
    for (int i = 0; i < 400; ++i, ++points) {
      const double x = 0.05 + 0.1 * i, y = 0.05 + 0.12 * j;
      bool on_boss = false;
      for (int a = 0; a < 6 && !on_boss; ++a)
        for (int b = 0; b < 4 && !on_boss; ++b) on_boss = std::hypot(x - (5 + 6 * a), y - (5 + 6.5 * b)) < 1.45;
      const double top = on_boss ? 7 : 5;
      const double distance = nominal.closest({x, y, top + 0.01}).distance;
      // The true distance is 0.01 mm except within 0.05 mm of a boss's wall (left out of the check).
      bool near_wall = false;
      for (int a = 0; a < 6; ++a)
        for (int b = 0; b < 4; ++b) near_wall = near_wall || std::fabs(std::hypot(x - (5 + 6 * a), y - (5 + 6.5 * b)) - 1.5) < 0.05;
      if (!near_wall) worst = std::fmax(worst, std::fabs(distance - 0.01));
    }
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  std::printf("plate with 24 bosses, STEP: %zu faces, read and meshed in %.2f s; %zu points in %.2f s (%.0f us a point), "
              "worst |distance - 0.01| %.2g mm away from the bosses' walls, %zu measured on the mesh\n",
              nominal.face_count(), read_s, points, seconds, 1e6 * seconds / static_cast<double>(points), worst,
              nominal.mesh_fallbacks());
  std::remove(path.c_str());
  return 0;
}

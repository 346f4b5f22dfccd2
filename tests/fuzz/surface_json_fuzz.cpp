// Fuzzes the SURF.json reader: damaged files give a clear error, never a crash; what it accepts
// evaluates, surface by surface and face by face.
#include <cmath>
#include <stdexcept>
#include <string>

#include "host/cad/surface_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const dg::host::FittedSurface f =
        dg::host::parse_surface_json(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
    // One surface, or trimmed faces (then `surface` is empty): each is evaluated, and each face's
    // loops are asked whether they hold a point.
    auto evaluate = [](const dg::host::BSplineSurface& s) {
      const dg::host::Point3 p = s.evaluate(0.5 * (s.u_min() + s.u_max()), 0.5 * (s.v_min() + s.v_max()));
      (void)p;
    };
    if (f.faces.empty()) evaluate(f.surface);
    for (const dg::host::TrimmedFace& face : f.faces) {
      evaluate(face.surface);
      const dg::host::Point2& v = face.loops[0][0];
      (void)dg::host::inside_face(face, v.x, v.y);
      (void)dg::host::point_above(face.surface, v.x, v.y);
    }
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}

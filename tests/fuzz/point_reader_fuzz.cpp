// Fuzzes the CSV, XYZ and PLY point readers and the height maps' (bCNC, Candle, Klipper): bad
// bytes give PointFileError, never a crash.
#include <string>

#include "host/scan/height_map.h"
#include "host/scan/ply_reader.h"
#include "host/scan/point_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  // The first byte picks the reader so one corpus explores all six.
  const uint8_t kind = data[0] % 6;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    if (kind == 0) dg::host::parse_csv_points(text, "fuzz.csv");
    if (kind == 1) dg::host::parse_xyz_points(text, "fuzz.xyz");
    if (kind == 2) dg::host::parse_ply_points(data + 1, size - 1, "fuzz.ply");
    if (kind == 3) dg::host::parse_bcnc_probe(text, "fuzz.probe");
    if (kind == 4) dg::host::parse_candle_map(text, "fuzz.map");
    if (kind == 5) dg::host::parse_klipper_mesh(text, "fuzz.cfg");
  } catch (const dg::host::PointFileError&) {
  }
  return 0;
}

// Deviation files: the CSV keeps six decimals (a nanometre); the PLY stores the coordinates as
// doubles and the deviation as a float, whose 24-bit mantissa is finer than 0.1 nm below 1 mm.
#include "host/inspect/deviation_file.h"

#include <cstdio>
#include <cstring>

namespace dg::host {

std::string format_deviations_csv(const std::vector<PointDeviation>& points) {
  std::string text = "x,y,z,deviation,beyond_edge\n";
  char line[160];
  for (const PointDeviation& d : points) {
    std::snprintf(line, sizeof line, "%.6f,%.6f,%.6f,%.6f,%d\n", d.point.x, d.point.y, d.point.z, d.distance, d.beyond_edge ? 1 : 0);
    text += line;
  }
  return text;
}

std::string format_deviations_ply(const std::vector<PointDeviation>& points) {
  std::string bytes = "ply\nformat binary_little_endian 1.0\ncomment bench digitizer inspection, millimetres\nelement vertex " +
                      std::to_string(points.size()) +
                      "\nproperty double x\nproperty double y\nproperty double z\nproperty float scalar_deviation\n"
                      "property uchar scalar_beyond_edge\nend_header\n";
  for (const PointDeviation& d : points) {
    // x86 and ARM hosts are little endian, as the header says; memcpy keeps the bits exact.
    char record[29];
    const double xyz[3] = {d.point.x, d.point.y, d.point.z};
    const float deviation = static_cast<float>(d.distance);
    std::memcpy(record, xyz, sizeof xyz);
    std::memcpy(record + 24, &deviation, sizeof deviation);
    record[28] = d.beyond_edge ? 1 : 0;
    bytes.append(record, sizeof record);
  }
  return bytes;
}

}  // namespace dg::host

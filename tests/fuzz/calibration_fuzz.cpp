// Fuzzes the table calibration file's reader: a damaged file gives a clear error, never a crash, and
// what it accepts corrects points inside its travel and refuses those outside. The same bytes as
// an artefact's certificate (rows of one or two numbers) must parse or be refused the same way.
#include <cmath>
#include <stdexcept>
#include <string>

#include "host/scan/certificate_csv.h"
#include "host/scan/table_calibration.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const dg::host::TableCalibration c = dg::host::calibration_from_json(text, "fuzz.cal.json");
    dg::host::PointCloud cloud;
    cloud.points = {{c.x0_mm, c.y0_mm, 1.0}, {0.5 * (c.x0_mm + c.x1_mm()), 0.5 * (c.y0_mm + c.y1_mm()), 1.0}, {c.x1_mm(), c.y1_mm(), 1.0}};
    cloud.sigma = std::vector<double>(3, 1e-3);
    dg::host::apply_calibration(c, cloud, "fuzz.scan");
  } catch (const dg::host::CalibrationError&) {
  }
  for (size_t columns : {1, 2}) {
    try {
      for (const std::vector<double>& row : dg::host::parse_certificate_rows(text, "fuzz.csv", columns, "numbers")) {
        if (row.size() != columns) __builtin_trap();
        for (double v : row) {
          if (!std::isfinite(v)) __builtin_trap();
        }
      }
    } catch (const dg::host::CalibrationError&) {
    }
  }
  return 0;
}

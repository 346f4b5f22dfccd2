// The gauge stand's drift over a long scan, measured by reading the scan's first point again every
// few lines (ScanRequest.reference_every_lines) and removed by interpolating those readings in time.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "host/scan/scan_sink.h"

namespace dg::host {

struct DriftRemoval {
  size_t readings = 0;           // reference readings, not counting the scan's first point
  double largest_mm = 0;         // the largest |drift| they measured against the first point
  double interpolation_mm = 0;   // the largest bound on the straight-line interpolation's error
  double u_max_mm = 0;           // the largest standard uncertainty the removal adds to a point
};

// Takes the reference readings (POINT_REFERENCE) out of scan.points, and out of *sigma_mm where it
// holds one value per point. With `remove` and at least one reading, each point's z is corrected by
// the drift at its time: the readings less the scan's first point (same place, same approach),
// joined by straight lines in time and held after the last reading (a scan that ended early). Each
// point's standard uncertainty then gains the correction's own: the readings' noise through the
// interpolation weights (when *sigma_mm has the readings' uncertainties), and the interpolation's
// error bound M h^2 / 8 (M the drift's curvature from the readings' second differences, h the time
// between readings) as a rectangular distribution. Without readings, nothing changes and nullopt
// comes back; without `remove` (the points as measured), the readings only leave the points and
// nullopt comes back too. Throws std::invalid_argument, naming `name` and the reading, where a reading lies
// elsewhere than the scan's first point, is not later than the one before, or differs from it by
// more than 1 mm (the part or the gauge moved), or where the scan's first point is missing.
std::optional<DriftRemoval> remove_drift(ScanData& scan, std::vector<double>* sigma_mm, const std::string& name,
                                         bool remove = true);

}  // namespace dg::host

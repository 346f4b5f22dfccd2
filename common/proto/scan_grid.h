// The grid a ScanRequest describes: one definition for the device that walks it and the
// host that counts it.
#pragma once
#include <cstdint>

#include "digitizer.pb.h"

namespace dg {

struct ScanGrid {
  uint64_t points_per_line = 0;  // along x
  uint64_t lines = 0;            // along y
  uint64_t points() const { return points_per_line * lines; }
};

// False when the request has no extent, max < min, or a zero step.
bool scan_grid(const digitizer_ScanRequest& request, ScanGrid* grid);

}  // namespace dg

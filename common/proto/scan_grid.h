// The grid a ScanRequest describes: one definition for the device that walks it and the
// host that counts it.
#pragma once
#include <cstdint>

#include "digitizer.pb.h"

namespace dg {

struct ScanGrid {
  uint64_t points_per_line = 0;  // along x
  uint64_t lines = 0;            // along y
  // Reference readings (ScanRequest.reference_every_lines): one after every that many lines and
  // one after the last.
  uint64_t references = 0;
  uint64_t points() const { return points_per_line * lines; }
  // Everything the scan reads: the grid's points and the reference readings.
  uint64_t readings() const { return points() + references; }
};

// How fast a dial gauge's plunger falls after a part that drops away, when a fly scan's request
// does not say (ScanRequest.plunger_follow_um_s): 50 mm/s.
constexpr uint32_t kDefaultPlungerFollowUmS = 50000;

// False when the request has no extent, max < min, or a zero step.
bool scan_grid(const digitizer_ScanRequest& request, ScanGrid* grid);

}  // namespace dg

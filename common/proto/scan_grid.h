// The grid a ScanRequest describes: one definition for the device that walks it and the
// host that counts it.
#pragma once
#include <cstdint>
#include <cstring>
#include <type_traits>

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

// The request's mode as sent: nanopb stores any number from the wire in the enum field, and
// reading a number the enum does not name through its type is undefined, so it is copied out.
inline int32_t scan_mode_number(const digitizer_ScanRequest& request) {
  // The enum's own size: 4 bytes on the host, 1 where the compiler packs enums (arm-none-eabi).
  std::underlying_type_t<digitizer_ScanMode> mode = 0;
  static_assert(sizeof(request.mode) == sizeof(mode), "the field is stored in the enum's underlying type");
  std::memcpy(&mode, &request.mode, sizeof mode);
  return static_cast<int32_t>(mode);
}
inline bool flies(const digitizer_ScanRequest& request) { return scan_mode_number(request) == digitizer_ScanMode_SCAN_MODE_FLY; }

// False when the request has no extent, max < min, or a zero step.
bool scan_grid(const digitizer_ScanRequest& request, ScanGrid* grid);

}  // namespace dg

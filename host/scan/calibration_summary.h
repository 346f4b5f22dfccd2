// What a device keeps of a table calibration: its version, when it was measured, which parts it
// holds and the CRC of its file, so that any host can tell whether and when the device was
// calibrated, and whether its own file is that calibration.
#pragma once
#include <cstdint>
#include <string>

#include "digitizer.pb.h"
#include "host/scan/table_calibration.h"

namespace dg::host {

// The summary of calibration `c`, whose file holds `file_text`. Its time is the latest of its
// parts' (an ISO 8601 UTC time, as calibrate writes them; an unreadable one counts as none).
digitizer_CalibrationSummary summarize_calibration(const TableCalibration& c, const std::string& file_text);

// "travel map, axes, straightness, lead screws, gauge tilt, gauge scale" for a parts mask.
std::string calibration_parts_text(uint32_t parts);

// Seconds since 1970 (UTC) as "YYYY-MM-DDTHH:MM:SSZ"; "an unknown time" for 0.
std::string unix_to_utc(uint64_t seconds);

// "YYYY-MM-DDTHH:MM:SSZ" as seconds since 1970; 0 when the text is not such a time.
uint64_t utc_to_unix(const std::string& text);

}  // namespace dg::host

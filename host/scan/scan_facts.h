// What a scan file says about how its points were measured, in words for a report or `info`.
#pragma once
#include <string>
#include <vector>

#include "host/scan/scan_sink.h"

namespace dg::host {

// How each point was read: feed, samples and how they were combined, settling, approach.
std::string reading_settings(const digitizer_ScanRequest& request);

// One line each: the device and its gauge, the grid, the reading settings, the repeatability
// measured before the scan, the machine's calibration, the points and lines, the device time.
std::vector<std::string> scan_facts(const ScanData& data);

}  // namespace dg::host

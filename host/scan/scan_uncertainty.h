// Each point's standard uncertainty from what a scan file records about its own measurement: the
// repeatability measured at its first point, the gauge's reading step and the points' spread flags.
#pragma once
#include <string>
#include <vector>

#include "host/scan/scan_sink.h"

namespace dg::host {

struct ScanPointSigmas {
  std::vector<double> sigma_mm;  // one per point of the scan; empty when the scan cannot state them
  std::string from;              // what they were made of, for reports; or why there are none
};

// u^2 = s^2 + q^2 / 12 for every point, with s the repeatability's standard deviation (a single
// reading after a move away and back: positioning and gauge together, so an upper bound for a
// point that averaged several samples without moving) and q the gauge's reading step (its rounding,
// a rectangular distribution: GUM F.2.2.1). A point flagged POINT_SPREAD_HIGH had samples that
// disagreed by more than the spread tolerance T even when retaken; its true spread is not sent, so
// it is given (T / 2)^2 more, the least its samples' half-range was. No repeatability record: none.
ScanPointSigmas scan_point_sigmas(const ScanData& scan);

}  // namespace dg::host

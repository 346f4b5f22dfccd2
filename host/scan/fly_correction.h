// A scan on the fly made exact: each point moved to where the gauge latched its reading (the
// latch delay measured from the serpentine's two directions), and readings taken with the plunger
// off the part taken out.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "host/scan/scan_sink.h"

namespace dg::host {

struct FlyCorrection {
  double latch_delay_ms = 0;    // from the request to the gauge's latch, as the lines measured it
  double u_latch_delay_ms = 0;  // its standard uncertainty
  double feed_mm_s = 0;         // the lines' median feed
  double spacing_mm = 0;        // the median distance between neighbouring points of a line
  size_t lines = 0;             // lines that took part in the estimate
  size_t lifted = 0;            // points flagged POINT_LIFTED
  std::vector<size_t> lifted_lines;  // the lines they were on (each once, in order)
  double u_shift_mm = 0;        // the largest standard uncertainty of a point's correction along x
};

// The positions along a line of a fly scan are the table's at each request: here every point moves
// on by the table's speed from its request to the next (the last point: from the one before) times
// the latch delay, which interpolates the table's position at the latch between two requests. The delay is the one that brings each line into agreement with the
// mean of its two neighbours (which ran the other way, so a wrong delay shifts them apart by twice
// it): a scan of two lines compares the two. Each point's sigma (where *sigma_mm has one per point)
// gains the correction's uncertainty times the part's slope along the line. With `drop_lifted`,
// POINT_LIFTED points leave scan.points (and *sigma_mm) and are counted. Returns nullopt for a
// stop-and-go scan; throws std::invalid_argument, naming `name`, for a fly scan with fewer than two
// lines of at least three points (its delay cannot be measured).
std::optional<FlyCorrection> correct_fly_scan(ScanData& scan, std::vector<double>* sigma_mm, const std::string& name,
                                              bool drop_lifted = true);

// One line for the user: the delay with its u, the feed and spacing, and the lifted points.
std::string fly_summary(const FlyCorrection& fix);

}  // namespace dg::host

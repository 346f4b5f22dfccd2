// Splitting a continuous probe stream into scan lines (Hamdan 2010, section 2, eq. 2-3).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "host/geometry/point3.h"

namespace dg::host {

struct SegmentOptions {
  // A step longer than this many times the line's typical step starts a new line.
  // Hamdan 2010, Table 1: steps within a line vary by at most 1.3x between neighbours,
  // line changes are 3.6x to 4.4x the step before them; 2 sits between with margin.
  double length_ratio = 2.0;
  // A step turning more than this from the line's direction (in XY) starts a new
  // line: the cross feed of a serpentine scan is often no longer than a forward step.
  double max_turn_deg = 60.0;
};

// Returns the 0-based line index of every point. Fewer than 2 points form one line.
std::vector<uint32_t> segment_lines(const std::vector<Point3>& points,
                                    const SegmentOptions& options = SegmentOptions{});

}  // namespace dg::host

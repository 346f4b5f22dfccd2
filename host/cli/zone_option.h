// Parsing inspect's named regions: --zone NAME=X0:X1,Y0:Y1,TOL (or ...,LOWER:UPPER), a region with its
// own tolerance, and --datum NAME=X0:X1,Y0:Y1, a datum of the alignment.
#pragma once
#include <string>

#include "host/inspect/decision.h"

namespace dg::host {

// "seal=10:30,5:12,0.01" -> the box 10..30 x 5..12 mm with -0.01..+0.01 mm; "seal=10:30,5:12,-0.02:0.01"
// -> -0.02..+0.01 mm. The name is letters, digits, '_' and '-'. Throws std::invalid_argument
// naming the option and what is wrong.
ToleranceZone parse_tolerance_zone(const std::string& text);

// inspect's --datum NAME=X0:X1,Y0:Y1: a datum region, in the scan's coordinates (its limits unused).
ToleranceZone parse_datum_region(const std::string& text);

}  // namespace dg::host

// The gauge's reading step, found in the heights themselves when a file does not say it.
#pragma once
#include <vector>

#include "host/geometry/point3.h"

namespace dg::host {

// The reading step of values rounded to one: the largest of the usual gauge steps (0.1 um to 10 um,
// and 0.00005 and 0.0001 inch) that 99 % of the z values are whole multiples of; 0 when none is.
double detect_resolution_mm(const std::vector<Point3>& points);

// The standard uncertainty of a reading rounded to `step_mm`: step / sqrt(12), the GUM's rectangular
// distribution of a resolution. 0 for an unknown step (0).
double rounding_sigma_mm(double step_mm);

}  // namespace dg::host

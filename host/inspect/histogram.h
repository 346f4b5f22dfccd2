// The histogram of deviations as SVG (vector text, real fonts in any browser), with the tolerance's
// limits and the decision's uncertainty zones marked.
#pragma once
#include <string>

#include "host/inspect/decision.h"
#include "host/inspect/inspect.h"

namespace dg::host {

// `bins` bars over the deviations' range (widened to take in the tolerance's limits when there is
// a decision), each a <rect class="bar" data-count="N">; the limits as red lines and, inside them,
// the band of U where conformance is not proven shaded; x axis in mm with ticks, y in points.
// Empty inspections give an empty plot. `decision` may be null.
std::string deviation_histogram_svg(const Inspection& inspection, const Decision* decision, int bins = 60);

}  // namespace dg::host

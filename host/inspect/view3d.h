// The report's 3D view: the measured points, coloured by their deviation on the maps' scale, on a
// canvas the reader turns with the mouse (or the arrow keys); plain JavaScript in the page, nothing
// fetched.
#pragma once
#include <string>

#include "host/inspect/deviation_map.h"
#include "host/inspect/inspect.h"

namespace dg::host {

// HTML (a canvas and its script) for at most `max_points` points, evenly strided, coloured on
// `scale` (a diverging range of 0: the largest |deviation|). Empty for an inspection without points.
std::string view3d_html(const Inspection& inspection, const ColourScale& scale, size_t max_points = 20000);

}  // namespace dg::host

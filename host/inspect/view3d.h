// The report's 3D view: the measured points, coloured by their deviation on the maps' scale, drawn by
// three.js (Debian's, embedded in the page) in a view the reader turns, moves and zooms with the
// mouse or the keys; nothing fetched, so it works from a file opened offline.
#pragma once
#include <string>

#include "host/geometry/tessellate.h"
#include "host/inspect/deviation_map.h"
#include "host/inspect/inspect.h"

namespace dg::host {

// HTML (a canvas and its script) for at most `max_points` points, evenly strided, coloured on
// `scale` (a diverging range of 0: the largest |deviation|), over `surface` (the nominal's or the
// fitted surface's mesh, as mesh_for_view makes it) drawn in translucent grey when given. Empty
// for an inspection without points.
std::string view3d_html(const Inspection& inspection, const ColourScale& scale, const Mesh* surface = nullptr,
                        size_t max_points = 20000);

}  // namespace dg::host

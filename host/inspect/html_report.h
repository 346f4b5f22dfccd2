// The inspection report: one self-contained HTML file with the pictures embedded, the statistics,
// the fit's parameters and what was measured.
#pragma once
#include <string>
#include <vector>

#include "host/inspect/decision.h"
#include "host/inspect/deviation_map.h"
#include "host/inspect/inspect.h"
#include "host/inspect/inspection_json.h"
#include "host/geometry/fitted_surface.h"
#include "host/geometry/tessellate.h"

namespace dg::host {

struct ReportPicture {
  std::string caption;
  std::string png;  // the picture's bytes
  // The same picture as SVG, which the report shows when present: text in the reader's fonts, mm axes.
  std::string svg;
};

struct ReportInputs {
  std::string title = "Inspection report";
  std::string created;            // when, as text
  ReportFields fields;            // part, serial, operator, company
  std::string points_file, surface_file;
  std::vector<std::string> scan_facts;  // lines about the scan (device, points, lines, time)
  const FittedSurface* surface = nullptr;
  const Inspection* inspection = nullptr;
  const Decision* decision = nullptr;  // the tolerance's verdict, when one was asked
  std::vector<ReportPicture> pictures;
  // The surface the 3D view draws under the points (mesh_for_view), and what it is, for the caption.
  const Mesh* view_surface = nullptr;
  std::string view_surface_name;
};

std::string html_report(const ReportInputs& inputs);
std::string base64(const std::string& bytes);

// The report's pictures for an inspection: the signed deviation and Hamdan's (2010) X, Y and Z error
// maps (the components of point - foot), each as PNG; `svg` receives the deviation map as SVG.
// With `limits`, the deviation map's colours are the tolerance scale (tolerance_colour), so a part in
// tolerance looks it whatever its largest deviation and a point beyond a limit stands out; without,
// blue to red stretched to the data.
std::vector<ReportPicture> inspection_pictures(const Inspection& inspection, std::string* svg,
                                               const ToleranceLimits* limits = nullptr);

// The scale the deviation map and the 3D view share.
ColourScale deviation_scale(const ToleranceLimits* limits);

// The map of the fitted surface's expanded uncertainty U = 2u over the part (from the u grid in
// SURF.json, interpolated bilinearly and placed at the surface's x, y); empty png when the surface
// carries no uncertainty.
ReportPicture uncertainty_picture(const FittedSurface& surface);

}  // namespace dg::host

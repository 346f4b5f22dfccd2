// An inspection's summary as JSON: statistics and bands, with what was compared and how the points
// were aligned to it.
#pragma once
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "host/geometry/point3.h"
#include "host/inspect/decision.h"
#include "host/inspect/inspect.h"

namespace dg::host {

// A rigid alignment applied to the points before they were measured (measured -> nominal).
// One datum of a datum alignment: its region (in the scan's coordinates), what it fixed.
struct DatumSummary {
  std::string name;
  double x0_mm = 0, x1_mm = 0, y0_mm = 0, y1_mm = 0;
  size_t points = 0;
  std::string fixes;          // "tilt about x and y, height"
  double rms_after_mm = 0;    // its points to the nominal once aligned
};

struct AlignmentSummary {
  std::array<std::array<double, 3>, 3> rotation{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  Point3 translation_mm;
  double rotation_deg = 0;
  double rms_before_mm = 0, rms_after_mm = 0;  // point-to-surface RMS before and after it
  int iterations = 0;
  bool converged = false;
  size_t left_out = 0;  // points beyond 3 robust sigmas, left out of the last step
  size_t beyond_edge = 0;  // points beyond the nominal's edge, left out of the fit and the RMS
  int held = 0;            // freedoms the nominal's shape does not fix, held still
  std::vector<DatumSummary> datums;  // empty: a best fit of all the points; else the datums in order
};

// What a signed report names besides the numbers: the part, its serial number, who measured it and
// for whom. Empty fields are left out.
struct ReportFields {
  std::string part, serial, operator_name, company;
};

// A nominal measured against (not a fit of the points): what it is, and how many points were
// measured on its mesh because the exact search on a CAD part's faces found no distance.
struct NominalNote {
  std::string summary;               // "STEP, 54 faces ...", "a mesh of 1,200 triangles"
  size_t measured_on_mesh = 0;
  double mesh_deflection_mm = 0;     // how far that mesh may be from the exact part
};

// `alignment`: null when the points were measured where they are ("alignment": null).
// `decision`: the tolerance's verdict (null in the JSON when no tolerance was given).
std::string inspection_json_text(const Inspection& inspection, const std::string& points_file, const std::string& surface_file,
                                 const AlignmentSummary* alignment = nullptr, const Decision* decision = nullptr,
                                 const ReportFields& fields = ReportFields{}, const NominalNote* nominal = nullptr);

}  // namespace dg::host

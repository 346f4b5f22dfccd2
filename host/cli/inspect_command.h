// `digitizer inspect`: deviations of measured points from a surface, with statistics and bands.
#pragma once
#include <CLI/CLI.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "host/inspect/inspection_json.h"

namespace dg::host {

struct InspectArgs {
  std::string points, surface;
  std::vector<double> bands_mm = {0.005, 0.01, 0.02, 0.05, 0.1, 0.5};
  bool json = false;             // the summary as JSON on standard output
  std::string deviations_csv;    // per point: x,y,z,deviation,beyond_edge
  std::string report_html;       // the report, with its pictures beside it
  bool align = false;            // rigid best fit of the points to the surface first
  std::vector<std::string> datums;  // --datum NAME=X0:X1,Y0:Y1: a 3-2-1 datum alignment instead, in order
  // A profile tolerance to decide: --tolerance T (symmetric, +-T), or --upper and --lower (NaN: not
  // given), and the points' standard uncertainty when neither a sigma column nor the scan gives it.
  double tolerance_mm = 0;
  double upper_mm = NAN, lower_mm = NAN;
  std::vector<std::string> zones;  // --zone NAME=X0:X1,Y0:Y1,TOL: regions with tolerances of their own
  double point_u_mm = 0;
  // The report's part, serial number, operator and company; operator and company default to the
  // config file's `operator =` and `company =`.
  ReportFields fields;
  bool pdf = true;  // the report also as PDF beside it (printed by Chromium)
};

// inspect's exit codes beyond 0, 1 and 2: a tolerance proven not kept, or not proven either way.
constexpr int kExitInspectionFail = 4;
constexpr int kExitInspectionInconclusive = 5;

CLI::App* add_inspect_command(CLI::App& app, InspectArgs& args);
int run_inspect(const InspectArgs& args);

}  // namespace dg::host

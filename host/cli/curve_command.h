// `digitizer curve`: a planar profile as a clamped cubic B-spline (Hlavova 2021), to JSON, IGES or STEP.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

namespace dg::host {

enum class CurveMethod { kWithinUncertainty, kInterpolate, kApproximate, kPolygon };
const char* curve_method_name(CurveMethod method);  // as --method spells it: ce, interpolate, ...

struct CurveArgs {
  std::string input, output;
  CurveMethod method = CurveMethod::kWithinUncertainty;
  double distance_mm = 0.0003;  // ce: the probe's uncertainty
  int control_count = 0;        // approximate: control points (0: a third of the points, at least 4)
  bool quiet = false;
};

CLI::App* add_curve_command(CLI::App& app, CurveArgs& args);
int run_curve(const CurveArgs& args);

}  // namespace dg::host

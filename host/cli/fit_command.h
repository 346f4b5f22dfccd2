// `digitizer fit`: least-squares B-spline and Bezier surfaces, optionally to a tolerance.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

namespace dg::host {

enum class SurfaceModel { kBSpline, kBezier, kHermite };
enum class FitMethod { kLeastSquares, kIps };  // IPS: Bezier only
const char* model_name(SurfaceModel model);    // as SURF.json and --model spell it
const char* method_name(FitMethod method);

struct FitArgs {
  std::string input, output;
  SurfaceModel model = SurfaceModel::kBSpline;
  FitMethod method = FitMethod::kLeastSquares;
  int degree = 3;
  std::string ctrl;               // NxM control points; empty: automatic
  std::string param = "xy";
  double tolerance_mm = 0;        // 0: fit the given net once
  bool ignore_sigma = false;
  bool no_creases = false;        // B-splines: do not put multiple knots at detected creases
  bool no_regions = false;        // with a tolerance: one surface even where creases split the scan
  int replicas = 30;              // ips and hermite: Monte Carlo refits for the uncertainty (ips: ~3 s each)
  bool quiet = false;
};

CLI::App* add_fit_command(CLI::App& app, FitArgs& args);
// Returns the exit code: 0 fitted (and the tolerance kept), 3 tolerance refused (the best surface is
// written, marked as not kept). Throws FitError, PointFileError and std::invalid_argument.
int run_fit(const FitArgs& args);

constexpr int kExitToleranceRefused = 3;

}  // namespace dg::host

// The curve subcommand: read a profile, build the curve, measure distances along its normals, write.
#include "host/cli/curve_command.h"

#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>

#include "host/io/file_name.h"
#include "host/scan/point_reader.h"
#include "host/io/atomic_file.h"
#include "host/io/standard_output.h"
#include "host/cad/iges_writer.h"
#include "host/fit/profile_curve.h"
#include "host/cad/step_writer.h"

namespace dg::host {

namespace {

nlohmann::json stats_json(const DistanceStats& d) {
  return {{"count", d.count}, {"mean", d.mean}, {"median", d.median}, {"stddev", d.stddev},
          {"max", d.max},     {"min", d.min}};
}

void print_stats(const char* what, const DistanceStats& d) {
  std::printf("%s over %zu points: mean %.4f median %.4f std %.4f max %.4f min %.4f mm\n", what, d.count, d.mean,
              d.median, d.stddev, d.max, d.min);
}

}  // namespace

const char* curve_method_name(CurveMethod method) {
  switch (method) {
    case CurveMethod::kWithinUncertainty: return "ce";
    case CurveMethod::kInterpolate: return "interpolate";
    case CurveMethod::kApproximate: return "approximate";
    case CurveMethod::kPolygon: return "polygon";
  }
  return "?";
}

CLI::App* add_curve_command(CLI::App& app, CurveArgs& a) {
  CLI::App* cmd = app.add_subcommand("curve", "fit a planar profile (x, z) with a clamped cubic B-spline, by default one passing at the probe's uncertainty from every point");
  cmd->add_option("input", a.input, ".csv, .xyz, .ply or .scan profile points in mm (one plane y = constant)")
      ->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", a.output, "CURVE.json, or .igs / .stp for CAD")->required();
  cmd->add_option("--method", a.method,
                  "ce (passes at --distance from every point), interpolate (natural cubic), approximate (least "
                  "squares, --ctrl N) or polygon (the points as control polygon); default ce")
      ->transform(CLI::CheckedTransformer(std::map<std::string, CurveMethod>{{"ce", CurveMethod::kWithinUncertainty},
                                                                               {"interpolate", CurveMethod::kInterpolate},
                                                                               {"approximate", CurveMethod::kApproximate},
                                                                               {"polygon", CurveMethod::kPolygon}},
                                          CLI::ignore_case));
  cmd->add_option("--distance", a.distance_mm, "ce: the probe's uncertainty, mm")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--ctrl", a.control_count, "approximate: control points (default: a third of the points, at least 4)")
      ->check(CLI::Range(4, 100000));
  cmd->add_flag("-q,--quiet", a.quiet, "print nothing but errors");
  return cmd;
}

int run_curve(const CurveArgs& a) {
  const std::vector<Point3> points = read_points(a.input).points;
  check_profile(points, a.input);
  BSplineCurve curve;
  nlohmann::json extra = nlohmann::json::object();
  if (a.method == CurveMethod::kWithinUncertainty) {
    const CeCurve ce = curve_within_uncertainty(points, a.distance_mm);
    curve = ce.curve;
    extra["distance_mm"] = a.distance_mm;
    extra["trend_cubic"] = {{"a", ce.trend.a}, {"b", ce.trend.b}, {"c", ce.trend.c}, {"d", ce.trend.d}};
    if (!a.quiet) std::printf("trend cubic z = %.8f x^3 + %.8f x^2 + %.8f x + %.8f\n", ce.trend.a, ce.trend.b, ce.trend.c, ce.trend.d);
  } else if (a.method == CurveMethod::kInterpolate) {
    curve = interpolate_natural(points);
  } else if (a.method == CurveMethod::kApproximate) {
    const int n = a.control_count > 0 ? a.control_count : std::max(4, static_cast<int>(points.size()) / 3);
    ApproximationReport report;
    curve = approximate_clamped(points, n, &report);
    extra["parameter_corrections"] = report.corrections;
    if (!report.u_mm.empty()) {
      extra["uncertainty"] = {{"kind", "standard uncertainty across the curve at each point (k = 1)"},
                              {"max_mm", report.u_max_mm},
                              {"mean_mm", report.u_mean_mm},
                              {"u_mm", report.u_mm}};
    }
    if (!a.quiet) {
      std::printf("parameter correction: %d steps; RMS %.4f mm on chord-length parameters, %.4f mm orthogonal after\n",
                  report.corrections, report.chord_rms_mm, report.corrected_rms_mm);
      if (report.u_mm.empty()) {
        std::printf("standard uncertainty: not determined: %s\n", report.u_not_determined.c_str());
      } else {
        std::printf("standard uncertainty across the curve u (k = 1): max %.4f mean %.4f mm; U = 2u: max %.4f mm\n",
                    report.u_max_mm, report.u_mean_mm, 2 * report.u_max_mm);
      }
    }
  } else {
    curve = control_polygon_curve(points);
  }
  // Distances along the curve's normals; the inner points as Hlavova 2021 counts them (a clamped
  // curve passes through its ends).
  const DistanceStats all = distance_stats(curve_distances(curve, points));
  const std::vector<Point3> inner(points.begin() + 1, points.end() - 1);
  const DistanceStats inside = distance_stats(curve_distances(curve, inner));
  const FileFormat format = file_format(a.output);
  if (format == FileFormat::kIges) {
    IgesOptions options;
    options.file_name = base_name(a.output);
    write_iges_curves(a.output, {curve}, options);
  } else if (format == FileFormat::kStep) {
    StepOptions options;
    options.file_name = base_name(a.output);
    write_step_curves(a.output, {curve}, options);
  } else if (format == FileFormat::kJson) {
    nlohmann::json j;
    j["format"] = "digitizer-curve";
    j["version"] = 1;
    j["units"] = "mm";
    j["method"] = curve_method_name(a.method);
    j["degree"] = curve.degree;
    j["knots"] = curve.knots;
    nlohmann::json control = nlohmann::json::array();
    for (const Point3& p : curve.control) control.push_back({p.x, p.y, p.z});
    j["control_points"] = control;
    j["fit"] = {{"source", a.input}, {"distance", stats_json(all)}, {"distance_inner", stats_json(inside)}};
    for (auto& [key, value] : extra.items()) j["fit"][key] = value;
    write_file_atomically(a.output, j.dump(1) + "\n");
  } else {
    throw std::invalid_argument("a curve is written as .json, .igs/.iges or .stp/.step (got " + a.output + ")");
  }
  if (!a.quiet) {
    std::printf("%s: clamped cubic B-spline, %zu control points\n", curve_method_name(a.method), curve.control.size());
    print_stats("distance along normals", all);
    print_stats("the same without the two end points", inside);
    std::printf("wrote %s\n", output_name(a.output).c_str());
  }
  return 0;
}

}  // namespace dg::host

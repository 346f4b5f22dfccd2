// digitizer: the command-line front end (scan a part, export points, inspect scan files).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <stdexcept>

#include <unistd.h>

#include "host/cli/characterize_command.h"
#include "host/cli/curve_command.h"
#include "host/cli/device_commands.h"
#include "host/cli/fit_command.h"
#include "host/cli/inspect_command.h"
#include "host/cli/scan_command.h"
#include "host/cli/superquadric_command.h"
#include "host/cli/units.h"
#include "host/io/file_name.h"
#include "host/scan/lts_filter.h"
#include "host/scan/point_export.h"
#include "host/scan/point_reader.h"
#include "host/scan/segment.h"
#include "host/scan/scan_file.h"
#include "host/geometry/bspline_curve.h"
#include "host/geometry/clamp.h"
#include "host/cad/iges_writer.h"
#include "host/cad/mesh_writer.h"
#include "host/cad/step_writer.h"
#include "host/cad/surface_json.h"
#include "host/transport/transport.h"

namespace {

using namespace dg::host;

// Exit codes (docs/cli.md).
constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;  // device, transport or file error
constexpr int kExitUsage = 2;

// A surface file to CAD (IGES 5.3 entity 128, STEP AP214) or a mesh (STL, OBJ, PLY), in millimetres.
int run_export_surface(const std::string& input, const std::string& output, double chord_mm, bool edges) {
  const FittedSurface surface = read_surface_json(input);
  const bool iges = ends_with(output, ".igs") || ends_with(output, ".iges");
  const bool step = ends_with(output, ".stp") || ends_with(output, ".step");
  if (ends_with(output, ".stl") || ends_with(output, ".obj") || ends_with(output, ".ply")) {
    const Mesh mesh = tessellate(surface.surface, chord_mm);
    write_mesh(output, mesh);
    std::printf("wrote %zu triangles (chord error %.4f mm, asked %.4f) to %s\n", mesh.triangles.size(),
                mesh.chord_error_mm, chord_mm, output.c_str());
    return kExitOk;
  }
  if (!iges && !step) {
    throw std::invalid_argument("a surface exports to .igs/.iges, .stp/.step, .stl, .obj or .ply (got " + output + ")");
  }
  if (edges) {
    // The four edges as curves: IGES entity 126 or a STEP curve set, for trimming or sketching in CAD.
    const std::vector<BSplineCurve> curves = boundary_curves(clamp_ends(surface.surface));
    if (iges) {
      IgesOptions options;
      options.file_name = base_name(output);
      write_iges_curves(output, curves, options);
    } else {
      StepOptions options;
      options.file_name = base_name(output);
      write_step_curves(output, curves, options);
    }
    std::printf("wrote the surface's 4 edges as B-spline curves to %s\n", output.c_str());
    return kExitOk;
  }
  const std::string name = base_name(output);
  const std::time_t now = std::time(nullptr);
  char stamp[32];
  if (iges) {
    IgesOptions options;
    options.file_name = name;
    std::strftime(stamp, sizeof stamp, "%Y%m%d.%H%M%S", std::gmtime(&now));
    options.timestamp = stamp;
    write_iges(output, surface.surface, options);
  } else {
    StepOptions options;
    options.file_name = name;
    std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%S", std::gmtime(&now));
    options.timestamp = stamp;
    write_step(output, surface.surface, options);
  }
  std::printf("wrote %s surface (%d x %d control points, degree %d x %d) to %s\n", surface.model.c_str(),
              surface.surface.count_u, surface.surface.count_v, surface.surface.degree_u, surface.surface.degree_v,
              output.c_str());
  return kExitOk;
}

int run_export(const std::string& input, const std::string& output, double chord_mm, bool edges) {
  if (ends_with(input, ".json")) return run_export_surface(input, output, chord_mm, edges);
  if (edges) throw std::invalid_argument("--edges exports a surface's edges: give a SURF.json");
  const ScanData data = read_scan_file(input);
  for (const auto& w : data.warnings) std::fprintf(stderr, "digitizer: warning: %s\n", w.c_str());
  write_points(output, data.points);
  std::printf("wrote %zu points to %s\n", data.points.size(), output.c_str());
  return kExitOk;
}

int run_segment(const std::string& input, const std::string& output, double ratio, double turn_deg) {
  const PointCloud cloud = read_points(input);
  SegmentOptions options;
  options.length_ratio = ratio;
  options.max_turn_deg = turn_deg;
  const std::vector<uint32_t> lines = segment_lines(cloud.points, options);
  write_lines_csv(output, cloud.points, lines);
  std::printf("%zu points in %u lines -> %s\n", cloud.points.size(),
              lines.empty() ? 0u : lines.back() + 1, output.c_str());
  return kExitOk;
}

struct FilterArgs {
  std::string input, output, outliers;
  bool lts = false;
  LtsOptions options;
};

int run_filter(const FilterArgs& a) {
  if (!a.lts) throw std::invalid_argument("choose a filter: --lts");
  PointCloud cloud = read_points(a.input);
  const LtsResult r = lts_filter(cloud.points, a.options);
  std::vector<Point3> raw = cloud.points;
  for (size_t i = 0; i < cloud.points.size(); ++i) cloud.points[i].z = r.z[i];
  write_cloud_csv(a.output, cloud.points, cloud.line ? &*cloud.line : nullptr);
  std::printf("LTS %dx%d (%s neighbourhoods), %d iterations%s, residual sigma %.4f mm\n", a.options.window,
              a.options.window, r.gridded ? "grid" : "nearest-point", r.iterations, r.converged ? "" : " (not converged)",
              r.sigma_mm);
  std::printf("%zu outliers (|z - filtered| > %.1f sigma)\n", r.outliers.size(), a.options.outlier_sigmas);
  for (size_t k = 0; k < r.outliers.size() && k < 10; ++k) {
    const auto& o = r.outliers[k];
    std::printf("  point %zu at (%.3f, %.3f): z %.4f -> %.4f mm (%+.4f)\n", o.index + 1, raw[o.index].x, raw[o.index].y,
                raw[o.index].z, r.z[o.index], o.residual_mm);
  }
  if (r.outliers.size() > 10) std::printf("  ... %s\n", a.outliers.empty() ? "list them all with --outliers FILE.csv" : "all in the outliers file");
  if (!a.outliers.empty()) {
    std::vector<Point3> bad;
    for (const auto& o : r.outliers) bad.push_back(raw[o.index]);
    write_cloud_csv(a.outliers, bad, nullptr);
    std::printf("wrote outliers (measured values) to %s\n", a.outliers.c_str());
  }
  std::printf("wrote %zu filtered points to %s\n", cloud.points.size(), a.output.c_str());
  return kExitOk;
}

int run_info(const std::string& input) {
  const ScanData data = read_scan_file(input);
  if (data.device) {
    std::printf("device %s (%s, firmware %s)\n", data.device->device_id, data.device->board,
                data.device->firmware_version);
  }
  if (data.request) {
    const auto& r = *data.request;
    std::printf("request x %.3f..%.3f y %.3f..%.3f mm, step %.3f x %.3f mm, %s\n",
                r.x.min_nm * 1e-6, r.x.max_nm * 1e-6, r.y.min_nm * 1e-6, r.y.max_nm * 1e-6,
                r.step_x_nm * 1e-6, r.step_y_nm * 1e-6,
                r.pattern == digitizer_ScanPattern_PATTERN_RASTER ? "raster" : "serpentine");
  }
  print_summary(data, "");
  if (!data.done) std::printf("the scan did not finish (no ScanDone record)\n");
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench digitizer: scan parts on an XY table with a dial gauge"};
  app.require_subcommand(1);
  app.set_version_flag("--version", DIGITIZER_VERSION);

  ScanArgs scan;
  CLI::App* scan_cmd = add_scan_command(app, scan);
  PullArgs pull;
  CLI::App* pull_cmd = add_pull_command(app, pull);
  CurveArgs curve;
  CLI::App* curve_cmd = add_curve_command(app, curve);
  CharacterizeArgs characterize_args;
  CLI::App* characterize_cmd = add_characterize_command(app, characterize_args);
  SuperquadricArgs superquadric;
  CLI::App* superquadric_cmd = add_superquadric_command(app, superquadric);

  std::string export_in, export_out;
  CLI::App* export_cmd = app.add_subcommand("export", "write a scan's points as CSV or PLY, or a surface as IGES or STEP");
  export_cmd->add_option("input", export_in, "scan file, or SURF.json")->required()->check(CLI::ExistingFile);
  export_cmd->add_option("-o,--output", export_out, "points: .csv or .ply; a surface: .igs, .stp, or a mesh .stl, .obj, .ply")->required();
  double export_chord_mm = 0.01;
  export_cmd->add_option("--chord", export_chord_mm, "meshes: largest distance from the surface to its triangles, mm")
      ->capture_default_str()->check(CLI::PositiveNumber);
  bool export_edges = false;
  export_cmd->add_flag("--edges", export_edges, "IGES/STEP: write the surface's four edges as B-spline curves instead");

  std::string segment_in, segment_out;
  double segment_ratio = 2.0, segment_turn = 60.0;
  CLI::App* segment_cmd =
      app.add_subcommand("segment", "split a probe stream into scan lines (step-length ratio and turns)");
  segment_cmd->add_option("input", segment_in, ".csv, .xyz or .scan points in mm")
      ->required()->check(CLI::ExistingFile);
  segment_cmd->add_option("-o,--output", segment_out, "output CSV with a 0-based line column")->required();
  segment_cmd->add_option("--ratio", segment_ratio, "a step this many times the line's typical step starts a line")
      ->capture_default_str()->check(CLI::Range(1.1, 1000.0));
  segment_cmd->add_option("--turn", segment_turn, "a turn of more than this (degrees) starts a line")
      ->capture_default_str()->check(CLI::Range(1.0, 180.0));

  std::string info_in;
  CLI::App* info_cmd = app.add_subcommand("info", "summarise a scan file");
  info_cmd->add_option("input", info_in, "scan file")->required()->check(CLI::ExistingFile);

  FilterArgs filter;
  CLI::App* filter_cmd = app.add_subcommand("filter", "robust noise filter (seed 004 LTS); reports outliers");
  filter_cmd->add_option("input", filter.input, ".csv, .xyz, .ply or .scan points in mm")->required()->check(CLI::ExistingFile);
  filter_cmd->add_option("-o,--output", filter.output, "filtered points (.csv)")->required();
  filter_cmd->add_flag("--lts", filter.lts, "Least-Trimmed-Squares filter")->required();
  filter_cmd->add_option("--window", filter.options.window, "neighbourhood side (odd)")->capture_default_str()->check(CLI::Range(3, 15));
  filter_cmd->add_option("--order", filter.options.order, "local model: 0 constant (seed 004 exactly), 1 plane, 2 quadratic")
      ->capture_default_str()->check(CLI::Range(0, 2));
  filter_cmd->add_flag("--smooth", filter.options.replace_all, "replace every point by the estimate, not only outliers");
  filter_cmd->add_option("--h", filter.options.h, "residuals kept (default [n/2]+[(p+1)/2]: 13 of 25 for order 0)")->check(CLI::Range(1, 225));
  filter_cmd->add_option("--outlier-sigmas", filter.options.outlier_sigmas, "report points this many robust sigmas off")
      ->capture_default_str()->check(CLI::PositiveNumber);
  filter_cmd->add_option("--outliers", filter.outliers, "write the outliers' measured points to this CSV");

  FitArgs fit;
  CLI::App* fit_cmd = add_fit_command(app, fit);
  InspectArgs inspect_args;
  CLI::App* inspect_cmd = add_inspect_command(app, inspect_args);
  DeviceArgs device_args;
  add_device_commands(app, device_args);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  }
  try {
    if (*scan_cmd) return run_scan(scan);
    if (*export_cmd) return run_export(export_in, export_out, export_chord_mm, export_edges);
    if (*pull_cmd) return run_pull(pull);
    if (*curve_cmd) return run_curve(curve);
    if (*superquadric_cmd) return run_superquadric(superquadric);
    if (*characterize_cmd) return run_characterize(characterize_args);
    if (*info_cmd) return run_info(info_in);
    if (*segment_cmd) return run_segment(segment_in, segment_out, segment_ratio, segment_turn);
    if (*fit_cmd) return run_fit(fit);
    if (*inspect_cmd) return run_inspect(inspect_args);
    const int device_result = run_device_command(app, device_args);
    if (device_result >= 0) return device_result;
    if (*filter_cmd) return run_filter(filter);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "digitizer: %s\n", e.what());
    return kExitUsage;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "digitizer: %s\n", e.what());
    return kExitFailure;
  }
  return kExitUsage;
}

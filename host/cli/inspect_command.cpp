// The inspect subcommand: read points and a surface, measure, print or write the results.
#include "host/cli/inspect_command.h"

#include <algorithm>
#include <cstdio>

#include "host/scan/point_reader.h"
#include "host/surface/atomic_file.h"
#include "host/surface/inspect.h"
#include "host/surface/inspection_json.h"
#include "host/surface/surface_json.h"

namespace dg::host {

CLI::App* add_inspect_command(CLI::App& app, InspectArgs& a) {
  CLI::App* cmd = app.add_subcommand("inspect", "deviations of measured points from a surface (orthogonal, signed)");
  cmd->add_option("points", a.points, ".csv, .xyz, .ply or .scan points in mm")->required()->check(CLI::ExistingFile);
  cmd->add_option("surface", a.surface, "SURF.json")->required()->check(CLI::ExistingFile);
  cmd->add_option("--band", a.bands_mm, "count the points within these deviations, mm")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_flag("--json", a.json, "print the summary as JSON");
  cmd->add_option("--deviations", a.deviations_csv, "write x,y,z,deviation per point to this CSV");
  return cmd;
}

int run_inspect(const InspectArgs& a) {
  const PointCloud cloud = read_points(a.points);
  const SurfaceFile surface = read_surface_json(a.surface);
  std::vector<double> bands = a.bands_mm;
  std::sort(bands.begin(), bands.end());
  const Inspection r = inspect(cloud.points, surface.surface, bands);
  if (!a.deviations_csv.empty()) {
    std::string text = "x,y,z,deviation\n";
    char line[160];
    for (const PointDeviation& d : r.points) {
      std::snprintf(line, sizeof line, "%.6f,%.6f,%.6f,%.6f\n", d.point.x, d.point.y, d.point.z, d.distance);
      text += line;
    }
    write_file_atomically(a.deviations_csv, text);
  }
  if (a.json) {
    std::fputs(inspection_json_text(r, a.points, a.surface).c_str(), stdout);
    return 0;
  }
  const DistanceStats& s = r.stats;
  std::printf("%zu points against %s (%s, %d x %d control points)\n", s.count, a.surface.c_str(), surface.model.c_str(),
              surface.surface.count_u, surface.surface.count_v);
  std::printf("orthogonal deviation: mean %.4f median %.4f std %.4f rms %.4f max %.4f min %.4f mm\n", s.mean, s.median,
              s.stddev, s.rms, s.max, s.min);
  for (const Band& b : r.bands) std::printf("within %.4f mm: %zu points (%.1f %%)\n", b.limit_mm, b.count, 100.0 * b.share);
  if (!a.deviations_csv.empty()) std::printf("wrote %s\n", a.deviations_csv.c_str());
  return 0;
}

}  // namespace dg::host

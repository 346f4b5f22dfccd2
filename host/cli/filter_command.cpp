// Filtering: outliers are left out of the filtered points (or replaced by the robust local estimate
// on request) and always listed with their measured values in a file of their own, as are the
// points the filter could not judge.
#include "host/cli/filter_command.h"

#include <cstdio>
#include <stdexcept>
#include <vector>

#include "host/io/file_name.h"
#include "host/io/standard_output.h"
#include "host/scan/point_export.h"
#include "host/scan/point_reader.h"

namespace dg::host {

CLI::App* add_filter_command(CLI::App& app, FilterArgs& a) {
  CLI::App* cmd = app.add_subcommand("filter", "robust noise filter (Least-Trimmed-Squares); reports outliers");
  cmd->add_option("input", a.input, ".csv, .xyz, .ply or .scan points in mm")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", a.output, "filtered points (.csv)")->required();
  // The LTS filter is the one method; --lts names it for scripts written when it had to be given.
  cmd->add_flag("--lts", "the Least-Trimmed-Squares filter (the default)");
  cmd->add_option("--window", a.options.window, "neighbourhood side (odd)")->capture_default_str()->check(CLI::Range(3, 15));
  cmd->add_option("--order", a.options.order, "local model: 0 constant (the classic LTS filter), 1 plane, 2 quadratic")
      ->capture_default_str()->check(CLI::Range(0, 2));
  cmd->add_flag("--smooth", a.options.replace_all, "replace every point by the estimate, not only outliers");
  cmd->add_option("--h", a.options.h, "residuals kept (default [n/2]+[(p+1)/2]: 13 of 25 for order 0)")->check(CLI::Range(1, 225));
  cmd->add_option("--outlier-sigmas", a.options.outlier_sigmas, "report points this many robust sigmas off")
      ->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--outliers", a.outliers, "the outliers' measured points (.csv; default OUTPUT.outliers.csv)");
  cmd->add_option("--unjudged", a.unjudged,
                  "the points kept as measured but not judged, where the grid does not resolve the surface (.csv; default "
                  "OUTPUT.unjudged.csv)");
  cmd->add_flag("--replace-outliers", a.replace_outliers,
                "put the local estimate in each outlier's place (default: leave outliers out of the output)");
  return cmd;
}

int run_filter(const FilterArgs& a) {
  const PointCloud cloud = read_points(a.input);
  // Below the smallest window the filter has (3 x 3), no point has neighbours enough to be judged
  // by, and the scatter it would print is that of a handful of points (one point gave "residual
  // sigma 0.0000 mm" and success).
  if (cloud.points.size() < kLtsFewestPoints) {
    throw std::runtime_error(a.input + ": " + std::to_string(cloud.points.size()) + " point" +
                             (cloud.points.size() == 1 ? "" : "s") + ": the LTS filter needs at least " +
                             std::to_string(kLtsFewestPoints) + " (one 3 x 3 window) to judge any of them");
  }
  LtsOptions options = a.options;
  if (cloud.resolution_mm) options.resolution_mm = *cloud.resolution_mm;  // the scan file says it
  const LtsResult r = lts_filter(cloud.points, options);
  // An outlier's place is left empty unless asked otherwise: near a crease a point on a sliver of
  // surface can be flagged although it is right, and its estimate then comes from the other side
  // of the crease; a missing point costs the fit little, a wrong height is a false measurement.
  std::vector<bool> is_outlier(cloud.points.size(), false);
  for (const auto& o : r.outliers) is_outlier[o.index] = true;
  PointCloud kept;
  if (cloud.line) kept.line = std::vector<uint32_t>();
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    if (is_outlier[i] && !a.replace_outliers) continue;
    kept.points.push_back({cloud.points[i].x, cloud.points[i].y, r.z[i]});
    if (cloud.line) kept.line->push_back((*cloud.line)[i]);
  }
  write_cloud_csv(a.output, kept.points, kept.line ? &*kept.line : nullptr);
  char settled[96] = "";
  if (!r.converged) {
    std::snprintf(settled, sizeof settled, r.alternating > 0 ? " (stopped: %zu points alternate between trimmed fits)" : " (not converged)",
                  r.alternating);
  }
  char step[96] = "";
  if (r.sigma_is_resolution) {
    std::snprintf(step, sizeof step, " (the reading step's %.4f mm / sqrt(12): the readings scatter less)", r.resolution_mm);
  }
  std::printf("LTS %dx%d (%s neighbourhoods), %d iterations%s, residual sigma %.4f mm%s\n", a.options.window,
              a.options.window, r.gridded ? "grid" : "nearest-point", r.iterations, settled, r.sigma_mm, step);
  std::printf("%zu outliers (|z - estimate| > %.1f sigma)%s\n", r.outliers.size(), a.options.outlier_sigmas,
              r.outliers.empty() ? "" : a.replace_outliers ? ", replaced by the estimate" : ", left out of the output");
  const auto& raw = cloud.points;
  for (size_t k = 0; k < r.outliers.size() && k < 10; ++k) {
    const auto& o = r.outliers[k];
    std::printf("  point %zu at (%.3f, %.3f): z %.4f, estimate %.4f mm (%+.4f)\n", o.index + 1, raw[o.index].x,
                raw[o.index].y, raw[o.index].z, r.z[o.index], o.residual_mm);
  }
  if (r.outliers.size() > 10) std::printf("  ... all in the outliers file\n");
  if (!r.unjudged.empty()) {
    std::printf("%zu points not judged, kept as measured: no model of their neighbours describes the surface there "
                "(steeper or more curved than the grid resolves; scan finer to judge them)\n",
                r.unjudged.size());
    for (size_t k = 0; k < r.unjudged.size() && k < 5; ++k) {
      const Point3& p = raw[r.unjudged[k]];
      std::printf("  point %zu at (%.3f, %.3f): z %.4f\n", r.unjudged[k] + 1, p.x, p.y, p.z);
    }
    if (r.unjudged.size() > 5) std::printf("  ... all in the list of points not judged\n");
  }
  // A list goes beside the output; with the output on standard output, in the current directory
  // after the input.
  auto list_name = [&](const std::string& given, const char* suffix) {
    return !given.empty()                ? given
           : is_standard_output(a.output) ? without_extension(base_name(a.input)) + suffix
                                          : without_extension(a.output) + suffix;
  };
  auto write_list = [&](const std::string& path, const std::vector<size_t>& indices, const char* what) {
    std::vector<Point3> listed;
    for (size_t i : indices) listed.push_back(raw[i]);
    write_cloud_csv(path, listed, nullptr);
    std::printf("wrote the %s (measured values) to %s\n", what, path.c_str());
  };
  if (!r.outliers.empty()) {
    std::vector<size_t> indices;
    for (const auto& o : r.outliers) indices.push_back(o.index);
    write_list(list_name(a.outliers, ".outliers.csv"), indices, "outliers");
  }
  if (!r.unjudged.empty()) write_list(list_name(a.unjudged, ".unjudged.csv"), r.unjudged, "points not judged");
  std::printf("wrote %zu filtered points to %s\n", kept.points.size(), output_name(a.output).c_str());
  return 0;
}

}  // namespace dg::host

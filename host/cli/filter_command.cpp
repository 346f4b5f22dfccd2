// Filtering: outliers are replaced by the robust local estimate and listed with their measured values.
#include "host/cli/filter_command.h"

#include <cstdio>
#include <stdexcept>
#include <vector>

#include "host/scan/point_export.h"
#include "host/scan/point_reader.h"

namespace dg::host {

CLI::App* add_filter_command(CLI::App& app, FilterArgs& a) {
  CLI::App* cmd = app.add_subcommand("filter", "robust noise filter (Least-Trimmed-Squares); reports outliers");
  cmd->add_option("input", a.input, ".csv, .xyz, .ply or .scan points in mm")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", a.output, "filtered points (.csv)")->required();
  cmd->add_flag("--lts", a.lts, "Least-Trimmed-Squares filter")->required();
  cmd->add_option("--window", a.options.window, "neighbourhood side (odd)")->capture_default_str()->check(CLI::Range(3, 15));
  cmd->add_option("--order", a.options.order, "local model: 0 constant (the classic LTS filter), 1 plane, 2 quadratic")
      ->capture_default_str()->check(CLI::Range(0, 2));
  cmd->add_flag("--smooth", a.options.replace_all, "replace every point by the estimate, not only outliers");
  cmd->add_option("--h", a.options.h, "residuals kept (default [n/2]+[(p+1)/2]: 13 of 25 for order 0)")->check(CLI::Range(1, 225));
  cmd->add_option("--outlier-sigmas", a.options.outlier_sigmas, "report points this many robust sigmas off")
      ->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--outliers", a.outliers, "write the outliers' measured points to this CSV");
  return cmd;
}

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
  return 0;
}

}  // namespace dg::host

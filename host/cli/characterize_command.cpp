// The characterize subcommand: per-point CSV (derivatives, H, K, type, region) and a summary.
#include "host/cli/characterize_command.h"

#include <cstdio>
#include <sstream>

#include "host/scan/point_reader.h"
#include "host/io/atomic_file.h"
#include "host/io/standard_output.h"
#include "host/fit/characterize.h"

namespace dg::host {

CLI::App* add_characterize_command(CLI::App& app, CharacterizeArgs& a) {
  CLI::App* cmd = app.add_subcommand("characterize", "curvatures, surface types and regions of a height field, from local quadratic fits");
  cmd->add_option("input", a.input, ".csv, .xyz, .ply or .scan points in mm")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", a.output, "OUT.csv: x,y,z,fx,fy,fxx,fxy,fyy,H,K,type,region per point")->required();
  cmd->add_option("--neighbours", a.neighbours, "points in each local quadratic fit")->capture_default_str()->check(CLI::Range(6, 400));
  cmd->add_flag("--robust", a.robust, "LTS-filter the heights first (outliers do not bend the quadratics)");
  cmd->add_option("--zero", a.zero_curvature, "curvature (1/mm) below which it counts as zero (default: from the noise)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("-q,--quiet", a.quiet, "print nothing but errors");
  return cmd;
}

int run_characterize(const CharacterizeArgs& a) {
  const PointCloud cloud = read_points(a.input);
  CharacterizeOptions options;
  options.neighbours = a.neighbours;
  options.robust = a.robust;
  options.zero_curvature = a.zero_curvature;
  const Characterization c = characterize(cloud, options);
  std::ostringstream csv;
  csv.precision(10);
  csv << "x,y,z,fx,fy,fxx,fxy,fyy,H,K,type,region\n";
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const Point3& p = cloud.points[i];
    const PointCharacter& q = c.points[i];
    csv << p.x << ',' << p.y << ',' << p.z << ',' << q.fx << ',' << q.fy << ',' << q.fxx << ',' << q.fxy << ',' << q.fyy << ','
        << q.mean_curvature << ',' << q.gaussian_curvature << ',' << (q.determined ? surface_type_name(q.type) : "undetermined")
        << ',' << q.region << '\n';
  }
  write_file_atomically(a.output, csv.str());
  if (!a.quiet) {
    std::printf("%zu points, curvature below %.3g 1/mm counts as zero\n", cloud.points.size(), c.zero_curvature);
    for (int t = 0; t < 8; ++t) {
      if (c.type_counts[t] > 0) std::printf("  %-13s %zu points\n", surface_type_name(static_cast<SurfaceType>(t)), c.type_counts[t]);
    }
    if (c.undetermined > 0) {
      std::printf("  %zu points not characterized: their %d nearest neighbours do not determine a quadratic (too few "
                  "distinct rows or columns among them)\n",
                  c.undetermined, options.neighbours);
    }
    std::printf("%u regions of one type (%u of at least 5 points); at most %d along x and %d along y\n", c.regions,
                c.significant_regions, c.regions_across_x, c.regions_across_y);
    if (c.suggested_control_x > 0 && c.suggested_control_y > 0) {
      std::printf("suggested cubic B-spline net: --ctrl %dx%d\n", c.suggested_control_x, c.suggested_control_y);
    } else {
      std::printf("no cubic B-spline net can be suggested: the points take %zu distinct positions along x and %zu along y, "
                  "and a cubic needs 4 in each\n",
                  c.distinct_x, c.distinct_y);
    }
    for (double x : c.creases_x_mm) std::printf("crease or step across the scan at x = %.3f mm\n", x);
    for (double y : c.creases_y_mm) std::printf("crease or step across the scan at y = %.3f mm\n", y);
    std::printf("wrote %s\n", output_name(a.output).c_str());
  }
  return 0;
}

}  // namespace dg::host

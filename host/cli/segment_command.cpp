// Segmenting a probe stream by the ratio of successive step lengths and by turns.
#include "host/cli/segment_command.h"

#include <cstdio>

#include "host/io/standard_output.h"
#include "host/scan/point_export.h"
#include "host/scan/point_reader.h"
#include "host/scan/segment.h"

namespace dg::host {

CLI::App* add_segment_command(CLI::App& app, SegmentArgs& a) {
  CLI::App* cmd = app.add_subcommand("segment", "split a probe stream into scan lines (step-length ratio and turns)");
  cmd->add_option("input", a.input, ".csv, .xyz, .ply or .scan points in mm")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", a.output, "output CSV with a 0-based line column")->required();
  cmd->add_option("--ratio", a.ratio, "a step this many times the line's typical step starts a line")
      ->capture_default_str()->check(CLI::Range(1.1, 1000.0));
  cmd->add_option("--turn", a.turn_deg, "a turn of more than this (degrees) starts a line")
      ->capture_default_str()->check(CLI::Range(1.0, 180.0));
  return cmd;
}

int run_segment(const SegmentArgs& a) {
  const std::string& input = a.input;
  const std::string& output = a.output;
  const PointCloud cloud = read_points(input);
  SegmentOptions options;
  options.length_ratio = a.ratio;
  options.max_turn_deg = a.turn_deg;
  const std::vector<uint32_t> lines = segment_lines(cloud.points, options);
  write_lines_csv(output, cloud.points, lines);
  std::printf("%zu points in %u lines -> %s\n", cloud.points.size(),
              lines.empty() ? 0u : lines.back() + 1, output_name(output).c_str());
  return 0;
}

}  // namespace dg::host

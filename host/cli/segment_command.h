// `digitizer segment`: split a probe stream into scan lines.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

namespace dg::host {

struct SegmentArgs {
  std::string input, output;
  double ratio = 2.0;     // a step this many times the line's typical step starts a line
  double turn_deg = 60.0; // a turn of more than this starts a line
};

CLI::App* add_segment_command(CLI::App& app, SegmentArgs& args);
int run_segment(const SegmentArgs& args);

}  // namespace dg::host

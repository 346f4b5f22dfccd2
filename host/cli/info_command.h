// `digitizer info`: what a scan file holds: device, request, points, lines, faults.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

namespace dg::host {

struct InfoArgs {
  std::string input;
};

CLI::App* add_info_command(CLI::App& app, InfoArgs& args);
int run_info(const InfoArgs& args);

}  // namespace dg::host

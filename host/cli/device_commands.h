// The device commands: devices, status, home, unlock, jog, abort, repeatability.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

namespace dg::host {

struct DeviceArgs {
  std::string device;  // --device; chosen_device() when empty
  bool json = false;          // status: as JSON
  double dx_mm = 0, dy_mm = 0;  // jog
  double feed_mm_s = 0;       // jog: 0 = the device's default
  unsigned count = 10;        // repeatability: readings
  std::string calibration;    // status: the table calibration scans use (the config's), to say whose and when
};

// Adds the subcommands; `run_device_command` runs whichever was given, or returns -1.
void add_device_commands(CLI::App& app, DeviceArgs& args);
int run_device_command(const CLI::App& app, const DeviceArgs& args);

}  // namespace dg::host

// `digitizer scan` (new or --resume) and `digitizer pull`: capturing from a device.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

#include "host/scan/scan_file.h"

namespace dg::host {

struct ScanArgs {
  std::string device;  // --device; chosen_device() when empty
  std::string x = "0:40", y = "0:30";
  double step_mm = 1.0;
  double step_y_mm = 0.0;
  std::string pattern = "serpentine";
  double feed_mm_s = 10.0;
  bool feed_given = false;  // --feed was given (on the fly the feed otherwise follows the gauge's cycle)
  std::string mode = "stop";  // stop (stop-and-go) or fly
  double plunger_mm_s = 0;   // on the fly: the plunger's fastest fall (0: the device's default)
  unsigned samples = 1;
  unsigned settle_ms = 0;
  double settle_um = 0;    // read until two successive readings agree within this
  double spread_um = 0;    // samples of a point must agree within this
  bool median = false;     // the median of the samples instead of their mean
  double approach_mm = 0;  // single-direction approach: overshoot this far, come back towards +
  uint32_t reference_every = 0;  // read the first point again after every this many lines (drift)
  unsigned repeatability = 0;  // readings of the first point before the scan, for each point's uncertainty; 0: none
  std::string calibration;  // --calibration: the table calibration recorded with the scan ("" or "none": none)
  std::string output;
  bool resume = false;     // continue the scan in `output` instead of starting one
  bool force = false;  // replace an existing -o
  int reconnect_s = 30;    // how long to try to reach a device again after a pulled cable
  bool adaptive = false;     // after the grid, new points where the part bends (host/cli/adaptive_scan.h)
  double tolerance_mm = 0;   // --adaptive: every point predicted by its neighbours within this
  double min_step_mm = 0;    // --adaptive: the finest step (0: --step / 8)
  std::string device_fit;  // pull the device's fit into this SURF.json after the scan
  std::string device_fit_model = "bezier";
  bool quiet = false;
};

struct PullArgs {
  std::string device;  // --device; chosen_device() when empty
  std::string model = "bezier";
  std::string output;
  std::string scan;  // --scan: the scan's file, for the fit's report and uncertainty
  bool quiet = false;
};

CLI::App* add_scan_command(CLI::App& app, ScanArgs& args);
CLI::App* add_pull_command(CLI::App& app, PullArgs& args);
// Exit codes: 0 done, 1 device/transport/file failure or a scan that ended early,
// kExitInterrupted after Ctrl-C (the scan is paused on the device and resumable).
int run_scan(const ScanArgs& args);
int run_pull(const PullArgs& args);

// Points, lines, extent and device time of a scan file, each line after `prefix`.
void print_summary(const ScanData& data, const char* prefix);

constexpr int kExitInterrupted = 130;

}  // namespace dg::host

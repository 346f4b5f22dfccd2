// A scan file summarised: who measured it, what was asked, and what arrived.
#include "host/cli/info_command.h"

#include <cstdio>

#include "host/cli/scan_command.h"
#include "host/scan/scan_facts.h"
#include "host/scan/scan_file.h"

namespace dg::host {

CLI::App* add_info_command(CLI::App& app, InfoArgs& a) {
  CLI::App* cmd = app.add_subcommand("info", "summarise a scan file");
  cmd->add_option("input", a.input, "scan file")->required()->check(CLI::ExistingFile);
  return cmd;
}

int run_info(const InfoArgs& a) {
  const ScanData data = read_scan_file(a.input);
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
    // How each point was read, so a scan taken with the config file's settings says which.
    std::printf("%s\n", reading_settings(r).c_str());
  }
  print_summary(data, "");
  // Which calibration corrects the points (the extent above is of the raw readings).
  for (const std::string& fact : scan_facts(data)) {
    if (fact.rfind("calibration:", 0) == 0) std::printf("%s\n", fact.c_str());
  }
  if (!data.done) std::printf("the scan did not finish (no ScanDone record)\n");
  return 0;
}

}  // namespace dg::host

// digitizer-sim: the device firmware on the simulated board, talking over an inherited fd.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "firmware/core/device.h"
#include "hw/sim/fd_link.h"
#include "hw/sim/sim_options.h"

namespace {

void usage() {
  std::fprintf(stderr,
               "usage: digitizer-sim [--fd N] [key=value ...]\n"
               "  --fd N      talk to the host over file descriptor N (default: stdin/stdout)\n"
               "  part=dome|saddle|canister|flat  seed=N  noise_um=X  outliers=RATE\n"
               "  outlier_mm=X  inch=0|1  gauge_delay_us=N  mute=0|1  drop_edge=BIT  id=NAME\n");
}

}  // namespace

int main(int argc, char** argv) {
  dg::sim::SimOptions options;
  int read_fd = 0, write_fd = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--fd") == 0 && i + 1 < argc) {
      read_fd = write_fd = std::atoi(argv[++i]);
      continue;
    }
    if (std::strcmp(argv[i], "--help") == 0) {
      usage();
      return 0;
    }
    const std::string error = dg::sim::apply_sim_option(argv[i], &options);
    if (!error.empty()) {
      std::fprintf(stderr, "digitizer-sim: %s\n", error.c_str());
      usage();
      return 2;
    }
  }
  dg::sim::FdLink link(read_fd, write_fd);
  dg::sim::SimBoard board(options.config, &link);
  dg::DeviceConfig device;
  device.motion.nm_per_step = options.config.nm_per_step;
  device.device_id = options.device_id.c_str();
  device.board = "sim";
  device.firmware_version = DIGITIZER_VERSION;
  device.capabilities = digitizer_Capability_CAP_DIGIMATIC | digitizer_Capability_CAP_DEVICE_FIT | digitizer_Capability_CAP_SIMULATED;
  device.gauge_resolution_nm = options.config.gauge.inch ? 2540 : 1000;
  // Virtual time runs hundreds of times faster than the host's clock during a scan: a 50 ms
  // retransmission timer would fire long before any host could answer (and resend frames the
  // host has, costing wire bytes). 5 s of virtual time is about 25 ms of real time during a scan;
  // lost frames are mostly resent sooner, on repeated acknowledgements.
  device.retransmit_us = 5000000;
  // The simulated gauge takes its time like a real one; allow for it.
  device.gauge.first_clock_timeout_us = options.config.gauge.request_to_clock_us + 100000;
  static dg::Device firmware(board, device);
  firmware.run();
  return 0;
}

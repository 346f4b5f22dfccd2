// digitizer-sim: the device firmware on the simulated board, talking over an inherited fd or
// waiting for hosts on a socket (--listen).
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include <csignal>
#include <memory>

#include "firmware/core/device.h"
#include "hw/sim/fd_link.h"
#include "hw/sim/listen_link.h"
#include "hw/sim/sim_device.h"
#include "hw/sim/sim_options.h"

namespace {

void usage() {
  std::fprintf(stderr,
               "usage: digitizer-sim [--fd N | --listen unix:PATH|tcp:[HOST:]PORT] [key=value ...]\n"
               "  --fd N      talk to the host over file descriptor N (default: stdin/stdout)\n"
               "  --listen A  wait for hosts on a socket, one at a time, until SIGTERM; the device\n"
               "              keeps its state between hosts (reach it with --device unix:PATH)\n"
               "  part=dome|saddle|canister|flat  seed=N  noise_um=X  outliers=RATE\n"
               "  outlier_mm=X  inch=0|1  gauge_delay_us=N  mute=0|1  drop_edge=BIT  id=NAME\n"
               "  host_silence_s=N (virtual s, 0 never)  on_host_silence=pause|continue|abort\n"
               "  start_x_mm=X start_y_mm=Y (the table's start)  estop_at_ms=T estop_ms=D  switches=0|1\n"
               "  require_homing=0|1  gauge=digimatic|caliper  backlash_um=X  compensate_um=X\n"
               "  touch_x_mm=X touch_y_mm=Y (faces the touch probe meets)\n");
}

}  // namespace

int main(int argc, char** argv) {
  dg::sim::SimOptions options;
  int read_fd = 0, write_fd = 1;
  std::string listen_at;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--listen") == 0 && i + 1 < argc) {
      listen_at = argv[++i];
      continue;
    }
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
  std::unique_ptr<dg::sim::LinkPort> link;
  if (!listen_at.empty()) {
    auto listener = std::make_unique<dg::sim::ListenLink>(listen_at);
    if (!listener->listening()) {
      std::fprintf(stderr, "digitizer-sim: %s\n", listener->error().c_str());
      return 1;
    }
    std::signal(SIGTERM, [](int) { dg::sim::ListenLink::request_stop(); });
    std::signal(SIGINT, [](int) { dg::sim::ListenLink::request_stop(); });
    if (listener->port() != 0) {
      std::printf("listening on tcp port %d\n", listener->port());
    } else {
      std::printf("listening on %s\n", listen_at.c_str());
    }
    std::fflush(stdout);
    link = std::move(listener);
  } else {
    link = std::make_unique<dg::sim::FdLink>(read_fd, write_fd);
  }
  dg::sim::SimBoard board(options.config, link.get());
  dg::DeviceConfig device = dg::sim::simulated_device(options);
  device.board = "sim";
  static dg::Device firmware(board, device);
  firmware.run();
  return 0;
}

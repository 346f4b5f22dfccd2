// digitizer-sim: the device firmware on the simulated board, talking over an inherited fd or
// waiting for hosts on a socket (--listen).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include <chrono>
#include <csignal>
#include <memory>
#include <new>

#include "firmware/core/device.h"
#include "hw/sim/fd_link.h"
#include "hw/sim/listen_link.h"
#include "hw/sim/sim_device.h"
#include "hw/sim/sim_options.h"

namespace {

uint64_t real_ms() {
  return static_cast<uint64_t>(std::chrono::duration_cast<std::chrono::milliseconds>(
                                   std::chrono::steady_clock::now().time_since_epoch())
                                   .count());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"digitizer-sim: the device firmware on a simulated table and gauge, in virtual time", "digitizer-sim"};
  int fd = -1;
  std::string listen_at;
  std::vector<std::string> settings;
  app.add_option("--fd", fd, "talk to the host over file descriptor N (default: stdin/stdout)")->check(CLI::NonNegativeNumber);
  app.add_option("--listen", listen_at,
                 "unix:PATH or tcp:[HOST:]PORT: wait for hosts there, one at a time, until SIGTERM; the device keeps "
                 "its state between hosts (reach it with --device unix:PATH)")
      ->excludes("--fd");
  app.add_option("settings", settings, "the simulated device, as key=value (below)");
  app.footer(dg::sim::kSimOptionsHelp);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  dg::sim::SimOptions options;
  for (const std::string& setting : settings) {
    const std::string error = dg::sim::apply_sim_option(setting, &options);
    if (!error.empty()) {
      std::fprintf(stderr, "digitizer-sim: %s (see --help)\n", error.c_str());
      return 2;
    }
  }
  const int read_fd = fd >= 0 ? fd : 0, write_fd = fd >= 0 ? fd : 1;
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
  board.set_real_clock(real_ms);
  // The settings flash in a file: read at power-up, written whole (then renamed) at every store.
  if (!options.settings_file.empty()) {
    std::vector<uint8_t> stored(64);
    if (FILE* in = std::fopen(options.settings_file.c_str(), "rb")) {
      const size_t got = std::fread(stored.data(), 1, stored.size(), in);
      std::fclose(in);
      board.preload_settings(stored.data(), got);
    }
    board.on_settings_stored(
        [](const uint8_t* data, size_t size, void* context) {
          const std::string& path = *static_cast<const std::string*>(context);
          const std::string temporary = path + ".new";
          FILE* out = std::fopen(temporary.c_str(), "wb");
          const bool written = out != nullptr && std::fwrite(data, 1, size, out) == size;
          if (out != nullptr && std::fclose(out) == 0 && written && std::rename(temporary.c_str(), path.c_str()) == 0) return true;
          std::fprintf(stderr, "digitizer-sim: could not keep the settings in %s\n", path.c_str());
          return false;
        },
        &options.settings_file);
  }
  dg::DeviceConfig device = dg::sim::simulated_device(options);
  device.board = "sim";
  // The firmware as the MCU runs it: a watchdog reset starts it again from scratch, on the same
  // table, part and link.
  alignas(dg::Device) static unsigned char firmware_storage[sizeof(dg::Device)];
  for (;;) {
    auto* firmware = new (firmware_storage) dg::Device(board, device);
    firmware->run();
    firmware->~Device();
    if (!board.take_reset()) break;
    std::fprintf(stderr, "digitizer-sim: the watchdog reset the device\n");
  }
  return 0;
}

// digitizer-gadget: the device firmware as a Linux process on a board with a USB device port (a
// Raspberry Pi Zero 2 W, say): USB through FunctionFS, the steppers, switches and gauge through
// libgpiod. With --simulate, the simulated table and gauge stand in for the pins (system tests and
// demonstrations of the USB path). Wiring and set-up: docs/hardware.md.
#include <csignal>
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "firmware/core/device.h"
#include "hw/boards/linux-gadget/configfs_gadget.h"
#include "hw/boards/linux-gadget/functionfs_link.h"
#include "hw/boards/linux-gadget/gpio_board.h"
#include "hw/sim/sim_device.h"
#include "hw/sim/sim_options.h"

namespace {

dg::gadget::FunctionFsLink* stop_target = nullptr;

std::string read_first_line(const char* path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  while (!line.empty() && (line.back() == '\0' || line.back() == '\n' || line.back() == ' ')) line.pop_back();
  return line;
}

// A serial that tells two controllers on one host apart: the SoC's (a Raspberry Pi's device tree
// has it), else the installation's machine id.
std::string default_serial() {
  std::string serial = read_first_line("/proc/device-tree/serial-number");
  if (serial.empty()) serial = read_first_line("/etc/machine-id").substr(0, 16);
  return serial.empty() ? "LINUX-GADGET" : serial;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"digitizer-gadget: the controller firmware as a Linux process: USB through FunctionFS, pins through libgpiod", "digitizer-gadget"};
  dg::gadget::GadgetSettings settings;
  std::string ffs_dir;
  std::vector<std::string> pin_specs, sim_settings;
  bool simulate = false, caliper = false, no_homing = false;
  app.add_option("--ffs", ffs_dir, "use the FunctionFS instance mounted at DIR (the gadget is made elsewhere)");
  app.add_option("--udc", settings.udc, "bind to this USB device controller (default: the first in /sys/class/udc)");
  std::string settings_file;
  app.add_option("--settings-file", settings_file,
                 "keep the device's settings (the calibration's summary) in FILE through a restart (default: none kept)");
  app.add_option("--serial", settings.serial, "the USB serial number (default: the board's serial or machine id)");
  app.add_option("--pin", pin_specs,
                 "KEY=LINE wires a pin: KEY is step_x dir_x step_y dir_y req ck data limit_x limit_y estop touch "
                 "enable; LINE is CHIP:OFFSET or a line name, '/active-low' after it inverts it, 'none' leaves the "
                 "pin unwired (default: the Raspberry Pi wiring in docs/hardware.md)")
      ->allow_extra_args(false);
  app.add_flag("--caliper", caliper, "a 24-bit caliper on the gauge port instead of a Digimatic gauge");
  app.add_flag("--no-homing", no_homing, "allow scans without homing first (a table without switches)");
  app.add_flag("--simulate", simulate, "the simulated table and gauge instead of GPIO, set up by key=value (below)");
  app.add_option("settings", sim_settings, "with --simulate: the simulated device, as key=value");
  app.footer(dg::sim::kSimOptionsHelp);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  const bool homing = !no_homing;
  dg::gadget::PinMap pins = dg::gadget::raspberry_pi_pins();
  dg::sim::SimOptions sim;
  std::string usage_error;
  for (const std::string& spec : pin_specs) {
    if (usage_error.empty()) dg::gadget::apply_pin(spec, &pins, &usage_error);
  }
  if (!sim_settings.empty() && !simulate) usage_error = "key=value settings go with --simulate";
  for (const std::string& setting : sim_settings) {
    if (usage_error.empty()) usage_error = dg::sim::apply_sim_option(setting, &sim);
  }
  if (!usage_error.empty()) {
    std::fprintf(stderr, "digitizer-gadget: %s (see --help)\n", usage_error.c_str());
    return 2;
  }
  if (settings.serial.empty()) settings.serial = default_serial();

  std::string error;
  // Declared before the link, so the link closes its endpoint files before the gadget goes.
  dg::gadget::ConfigfsGadget gadget;
  const bool make_gadget = ffs_dir.empty();
  if (make_gadget) {
    if (!gadget.create(settings, &error)) {
      std::fprintf(stderr, "digitizer-gadget: %s\n", error.c_str());
      return 1;
    }
    ffs_dir = settings.mount_dir;
  }
  dg::gadget::FunctionFsLink link(ffs_dir);
  if (!link.start(&error)) {
    std::fprintf(stderr, "digitizer-gadget: %s\n", error.c_str());
    return 1;
  }
  stop_target = &link;
  std::signal(SIGTERM, [](int) { stop_target->request_stop(); });
  std::signal(SIGINT, [](int) { stop_target->request_stop(); });

  std::unique_ptr<dg::sim::SimBoard> sim_board;
  std::unique_ptr<dg::gadget::GpioBoard> gpio_board;
  dg::hal::Board* board = nullptr;
  dg::DeviceConfig config;
  if (simulate) {
    sim.device_id = settings.serial;
    sim_board = std::make_unique<dg::sim::SimBoard>(sim.config, &link);
    config = dg::sim::simulated_device(sim);
    board = sim_board.get();
  } else {
    gpio_board = std::make_unique<dg::gadget::GpioBoard>(link);
    if (!gpio_board->open(pins, &error)) {
      std::fprintf(stderr, "digitizer-gadget: %s\n", error.c_str());
      return 1;
    }
    config = dg::hardware_device_config(caliper);
    config.device_id = settings.serial.c_str();
    config.require_homing = homing;
    if (!settings_file.empty()) gpio_board->keep_settings_in(settings_file);
    board = gpio_board.get();
  }
  config.board = simulate ? "gadget (sim)" : "linux-gadget";

  if (make_gadget) {
    if (!gadget.bind(&error)) {
      std::fprintf(stderr, "digitizer-gadget: %s\n", error.c_str());
      return 1;
    }
    std::printf("digitizer-gadget: serial %s on %s\n", settings.serial.c_str(), gadget.udc().c_str());
  } else {
    std::printf("digitizer-gadget: serial %s on %s\n", settings.serial.c_str(), ffs_dir.c_str());
  }
  std::fflush(stdout);
  auto device = std::make_unique<dg::Device>(*board, config);
  device->run();
  std::printf("digitizer-gadget: stopped; the host dropped the link %u times", link.drops());
  if (gpio_board) {
    std::printf(", %llu of %llu step ticks were late by more than 50 us, %llu gauge clock edges were left out (DATA doubtful)",
                static_cast<unsigned long long>(gpio_board->late_steps()),
                static_cast<unsigned long long>(gpio_board->timer_ticks()),
                static_cast<unsigned long long>(gpio_board->dropped_clock_edges()));
  }
  std::printf("\n");
  return 0;
}

// --device, then DIGITIZER_DEVICE, then the config file; else an error that says how to choose.
#include "host/cli/device_choice.h"

#include <cstdlib>
#include <stdexcept>

#include "host/cli/config_file.h"
#include "host/transport/usb_transport.h"

namespace dg::host {

namespace {

// The USB devices that answer, as "usb:VID:PID,serial=S" lines, or why none could be listed.
std::string usb_devices_found() {
  try {
    const UsbSelector ids = parse_usb_uri("usb:");
    std::string out;
    for (const UsbDeviceInfo& d : list_usb_devices(ids)) {
      char id[32];
      std::snprintf(id, sizeof id, "usb:%04x:%04x", d.vendor, d.product);
      out += std::string("  ") + id + (d.serial.empty() ? "" : ",serial=" + d.serial) + "\n";
    }
    return out.empty() ? "  (no USB device of ours is connected)\n" : out;
  } catch (const std::exception& e) {
    return std::string("  (USB devices could not be listed: ") + e.what() + ")\n";
  }
}

}  // namespace

std::string config_path() {
  const char* xdg = std::getenv("XDG_CONFIG_HOME");
  if (xdg && *xdg) return std::string(xdg) + "/digitizer/config";
  const char* home = std::getenv("HOME");
  return std::string(home && *home ? home : ".") + "/.config/digitizer/config";
}

std::string configured_value(const std::string& path, const std::string& key) {
  for (const ConfigEntry& e : read_config(path)) {
    if (e.key == key) return e.value;
  }
  return "";
}

std::string configured_device(const std::string& path) { return configured_value(path, "device"); }

std::string chosen_device(const std::string& option) {
  if (!option.empty()) return option;
  const char* from_environment = std::getenv("DIGITIZER_DEVICE");
  if (from_environment && *from_environment) return from_environment;
  const std::string path = config_path();
  const std::string configured = configured_device(path);
  if (!configured.empty()) return configured;
  throw std::invalid_argument(
      "no device named: give --device URI, set DIGITIZER_DEVICE, or write `device = URI` in " + path +
      ". Devices found:\n" + usb_devices_found() +
      "  sim:part=dome (the simulated table and gauge; also saddle, canister, flat)\n"
      "`digitizer devices` lists every kind.");
}

}  // namespace dg::host

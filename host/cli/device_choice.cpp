// --device, then DIGITIZER_DEVICE, then the config file; else an error that says how to choose.
#include "host/cli/device_choice.h"

#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include "host/transport/usb_transport.h"

namespace dg::host {

namespace {

std::string trimmed(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

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

namespace {

// The first `key = value` line of the config file (comments after '#'): its value and line number;
// false when there is no file or no such line.
bool find_setting(const std::string& path, const std::string& key, std::string& value, int& line_number) {
  std::ifstream in(path);
  std::string line;
  for (line_number = 1; in && std::getline(in, line); ++line_number) {
    const std::string text = trimmed(line.substr(0, line.find('#')));
    const size_t equals = text.find('=');
    if (equals == std::string::npos || trimmed(text.substr(0, equals)) != key) continue;
    value = trimmed(text.substr(equals + 1));
    return true;
  }
  return false;
}

}  // namespace

std::string configured_value(const std::string& path, const std::string& key) {
  std::string value;
  int line_number = 0;
  return find_setting(path, key, value, line_number) ? value : "";
}

std::string configured_device(const std::string& path) {
  std::string uri;
  int line_number = 0;
  if (!find_setting(path, "device", uri, line_number)) return "";
  if (uri.empty()) throw std::invalid_argument(path + ":" + std::to_string(line_number) + ": `device =` names no device");
  return uri;
}

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

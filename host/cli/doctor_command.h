// `digitizer doctor`: checks what a bench needs (config, udev rule, USB access, the device's
// firmware and protocol, the simulator, OpenCASCADE, Chromium) and says what to fix.
#pragma once
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace dg::host {

struct DoctorArgs {
  std::string device;  // also check this device (else DIGITIZER_DEVICE, the config file, every USB device found)
};

enum class Health { kOk, kWarning, kFailure };

struct Finding {
  Health verdict = Health::kOk;
  std::string what;  // what was found
  std::string fix;   // what to do about it ("" when nothing)
};

// Where the udev rule for VID:PID is: a rule in one of `read_directories` (those udev reads) is ok;
// one only in `installed_directory` (a prefix's lib/udev/rules.d, which udev does not read unless
// the prefix is /usr) or none is a warning that says how to put it in place.
Finding udev_rule_finding(const std::vector<std::string>& read_directories, const std::string& installed_directory,
                          uint16_t vendor, uint16_t product);

void add_doctor_command(CLI::App& app, DoctorArgs& args);

// Runs `doctor` when it was chosen: 0 when nothing failed, 1 when something must be fixed; -1
// when another command was chosen.
int run_doctor_command(const CLI::App& app, const DoctorArgs& args);

}  // namespace dg::host

// Each check is independent and says what it found; one that fails does not stop the others,
// so a new bench gets the whole list of what to fix at once.
#include "host/cli/doctor_command.h"

#include <dirent.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "host/cad/cad_nominal.h"
#include "host/cli/build_info.h"
#include "host/cli/config_file.h"
#include "host/cli/device_choice.h"
#include "host/cli/pdf_print.h"
#include "host/device/session.h"
#include "host/io/own_prefix.h"
#include "host/transport/sim_transport.h"
#include "host/transport/transport.h"
#include "host/transport/usb_transport.h"

namespace dg::host {

namespace {

// A rule file that names both IDs (as udev's ATTR{idVendor}=="1209" matches, lower-case hex).
std::string rule_in(const std::string& directory, uint16_t vendor, uint16_t product) {
  char vid[8], pid[8];
  std::snprintf(vid, sizeof vid, "%04x", vendor);
  std::snprintf(pid, sizeof pid, "%04x", product);
  DIR* d = opendir(directory.c_str());
  if (!d) return "";
  std::string found;
  while (const dirent* entry = readdir(d)) {
    const std::string name = entry->d_name;
    if (name.size() < 7 || name.compare(name.size() - 6, 6, ".rules") != 0) continue;
    std::ifstream in(directory + "/" + name);
    std::stringstream text;
    text << in.rdbuf();
    const std::string rules = text.str();
    if (rules.find("\"" + std::string(vid) + "\"") != std::string::npos &&
        rules.find("\"" + std::string(pid) + "\"") != std::string::npos) {
      found = directory + "/" + name;
      break;
    }
  }
  closedir(d);
  return found;
}

void print(const Finding& f) {
  const char* label = f.verdict == Health::kOk ? "ok  " : f.verdict == Health::kWarning ? "WARN" : "FAIL";
  std::printf("%s  %s\n", label, f.what.c_str());
  if (!f.fix.empty()) std::printf("      fix: %s\n", f.fix.c_str());
}

Finding config_finding() {
  const std::string path = config_path();
  try {
    const size_t settings = read_config(path).size();
    if (access(path.c_str(), F_OK) != 0) return {Health::kOk, "config file: none at " + path + " (every setting has its default)", ""};
    return {Health::kOk, "config file " + path + ": " + std::to_string(settings) + " settings (`digitizer config show`)", ""};
  } catch (const std::exception& e) {
    return {Health::kFailure, std::string("config file: ") + e.what(), "correct that line; docs/cli.md (Config file) lists the keys"};
  }
}

Finding device_finding(const std::string& uri) {
  try {
    auto transport = open_transport(uri);
    Session session(*transport);
    const digitizer_Hello h = session.hello(5000);
    char text[512];
    std::snprintf(text, sizeof text, "device %s: %s on %s, firmware %s, protocol %u..%u (this host speaks %d), capabilities: %s",
                  uri.c_str(), h.device_id, h.board, h.firmware_version, h.min_protocol_version, h.protocol_version,
                  static_cast<int>(digitizer_ProtocolVersion_PROTOCOL_VERSION), capability_names(h.capabilities).c_str());
    return {Health::kOk, text, ""};
  } catch (const std::exception& e) {
    return {Health::kFailure, "device " + uri + ": " + e.what(),
            "check the cable and that the board runs our firmware (scripts/flash); a protocol mismatch needs the "
            "firmware of this release"};
  }
}

}  // namespace

Finding udev_rule_finding(const std::vector<std::string>& read_directories, const std::string& installed_directory,
                          uint16_t vendor, uint16_t product) {
  for (const std::string& directory : read_directories) {
    const std::string rule = rule_in(directory, vendor, product);
    if (!rule.empty()) return {Health::kOk, "udev rule " + rule, ""};
  }
  char ids[16];
  std::snprintf(ids, sizeof ids, "%04x:%04x", vendor, product);
  const std::string installed = installed_directory.empty() ? "" : rule_in(installed_directory, vendor, product);
  if (!installed.empty()) {
    return {Health::kWarning, std::string("udev rule for ") + ids + " is installed at " + installed + ", where udev does not read it",
            "sudo cp " + installed + " /etc/udev/rules.d/ && sudo udevadm control --reload, then plug the board in again"};
  }
  return {Health::kWarning, std::string("no udev rule for ") + ids + ": only root can open the device",
          "scripts/install-udev-rule (or the digitizer package), then plug the board in again"};
}

void add_doctor_command(CLI::App& app, DoctorArgs& args) {
  CLI::App* doctor = app.add_subcommand("doctor", "check the set-up a bench needs and say what to fix (exit 1 when something must be)");
  doctor->add_option("--device", args.device, "also talk to this device (else DIGITIZER_DEVICE, the config file's, or every USB device found)");
}

int run_doctor_command(const CLI::App& app, const DoctorArgs& args) {
  if (!app.got_subcommand("doctor")) return -1;
  std::vector<Finding> findings;
  findings.push_back({Health::kOk,
                      std::string("digitizer ") + kBuildVersion + " (commit " + kBuildCommit + "), protocol " +
                          std::to_string(static_cast<int>(digitizer_ProtocolVersion_PROTOCOL_VERSION)),
                      ""});
  findings.push_back(config_finding());

  UsbSelector ids;
  try {
    ids = parse_usb_uri("usb:");
  } catch (const std::exception& e) {
    findings.push_back({Health::kFailure, e.what(), "set DIGITIZER_USB_ID=VVVV:PPPP in hex, or unset it"});
  }
  const std::string prefix = own_prefix();
  findings.push_back(udev_rule_finding({"/etc/udev/rules.d", "/run/udev/rules.d", "/lib/udev/rules.d", "/usr/lib/udev/rules.d"},
                                       prefix.empty() ? "" : prefix + "/lib/udev/rules.d", ids.vendor, ids.product));

  std::vector<std::string> devices;
  try {
    const std::vector<UsbDeviceInfo> found = list_usb_devices(ids);
    findings.push_back({Health::kOk, usb_library_version() + ": " + std::to_string(found.size()) + " device(s) of ours on USB", ""});
    for (const UsbDeviceInfo& d : found) {
      char where[64];
      std::snprintf(where, sizeof where, "USB device on bus %u address %u", d.bus, d.address);
      if (d.problem.empty()) {
        devices.push_back("usb:" + std::string(d.serial.empty() ? "" : "serial=" + d.serial));
      } else {
        findings.push_back({Health::kFailure, std::string(where) + " cannot be opened: " + d.problem,
                            "install the udev rule (above), add yourself to the plugdev group (sudo adduser $USER plugdev; "
                            "log in again) and plug the board in again"});
      }
    }
  } catch (const std::exception& e) {
    findings.push_back({Health::kWarning, usb_library_version() + " cannot reach USB here: " + e.what(),
                        "a real board needs USB (in a container, pass the bus through); the simulator does not"});
  }
  // The device a command would use, if one is named; else every USB device that could be opened.
  std::string named = args.device;
  if (named.empty()) {
    if (const char* environment = std::getenv("DIGITIZER_DEVICE"); environment && *environment) named = environment;
  }
  if (named.empty()) {
    try {
      named = configured_device(config_path());
    } catch (const std::exception&) {
      // Already reported by the config check.
    }
  }
  if (!named.empty()) devices = {named};
  for (const std::string& uri : devices) findings.push_back(device_finding(uri));
  if (devices.empty()) {
    findings.push_back({Health::kWarning, "no device to talk to: none named and none of ours on USB",
                        "connect the board, or name one (--device, DIGITIZER_DEVICE, `device =` in the config file)"});
  }

  const std::string simulator = find_simulator();
  const bool simulator_found = simulator.find('/') != std::string::npos && access(simulator.c_str(), X_OK) == 0;
  findings.push_back(simulator_found ? Finding{Health::kOk, "simulator " + simulator + " (sim: devices)", ""}
                                     : Finding{Health::kWarning, "no digitizer-sim beside digitizer: sim: devices look for it on the PATH",
                                               "install digitizer-sim next to digitizer, or set DIGITIZER_SIM"});
  try {
    findings.push_back(
        {Health::kOk, "OpenCASCADE " + opencascade_version() + " (STEP and IGES nominals for inspect)", ""});
  } catch (const CadNominalError& e) {
    findings.push_back(
        {Health::kFailure, e.what(), "reinstall the digitizer package: inspect cannot read STEP or IGES nominals"});
  }
  const std::string chromium = find_chromium();
  findings.push_back(!chromium.empty() ? Finding{Health::kOk, "Chromium " + chromium + " (the report's PDF)", ""}
                                       : Finding{Health::kWarning, "no Chromium: inspect writes its HTML report but no PDF",
                                                 "sudo apt install chromium (or set DIGITIZER_CHROMIUM)"});
  bool failed = false;
  for (const Finding& f : findings) {
    print(f);
    failed = failed || f.verdict == Health::kFailure;
  }
  std::printf("%s\n", failed ? "something must be fixed (FAIL above)" : "nothing must be fixed");
  return failed ? 1 : 0;
}

}  // namespace dg::host

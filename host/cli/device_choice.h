// Which device a command talks to: never a silent default (a simulator that "homes" with no
// hardware attached is a lie).
#pragma once
#include <string>

namespace dg::host {

// `option` (--device) if given; else the DIGITIZER_DEVICE environment variable; else the line
// `device = URI` of $XDG_CONFIG_HOME/digitizer/config (~/.config/digitizer/config). With none,
// throws std::invalid_argument listing the USB devices found and how to name one.
std::string chosen_device(const std::string& option);

// The config file's device, "" when there is no file or no such line. Throws std::invalid_argument
// for a file that is not a valid config (read_config; the line number said).
std::string configured_device(const std::string& config_path);

// The value of `key = value` in the config file, "" when there is no file or no such line; throws
// as read_config does.
std::string configured_value(const std::string& config_path, const std::string& key);

// Where the config file is looked for.
std::string config_path();

}  // namespace dg::host

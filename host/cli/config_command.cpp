// Prints every setting the config file may hold with its effective value and its source: the
// environment (device only), the config file's line, or the built-in default of its option.
#include "host/cli/config_command.h"

#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "host/cli/config_file.h"
#include "host/cli/device_choice.h"

namespace dg::host {

void add_config_command(CLI::App& app) {
  CLI::App* config = app.add_subcommand("config", "the config file's settings: `config show` prints each one's value and source");
  config->require_subcommand(1);
  config->add_subcommand("show", "print every setting's effective value and where it came from (command-line options still override)");
}

int run_config_command(const CLI::App& app) {
  if (!app.got_subcommand("config")) return -1;
  const std::string path = config_path();
  struct stat info {};
  const bool exists = stat(path.c_str(), &info) == 0;
  const std::vector<ConfigEntry> entries = read_config(path);
  std::printf("config file: %s%s\n", path.c_str(), exists ? "" : " (none: every setting has its default)");
  std::printf("%-14s %-24s %s\n", "setting", "value", "from");
  for (const ConfigSetting& s : config_settings()) {
    std::string value, source;
    for (const ConfigEntry& e : entries) {
      if (e.key == s.key) value = e.value, source = "config file, line " + std::to_string(e.line);
    }
    const char* environment = std::getenv("DIGITIZER_DEVICE");
    if (std::string(s.key) == "device" && environment && *environment) {
      value = environment, source = "DIGITIZER_DEVICE (overrides the config file)";
    }
    if (source.empty()) {
      const CLI::App* command = *s.command ? app.get_subcommand(s.command) : nullptr;
      const CLI::Option* option = command ? command->get_option_no_throw(s.option) : nullptr;
      const std::string fallback = option ? option->get_default_str() : "";
      value = fallback.empty() ? "-" : fallback;
      source = *s.command ? (fallback.empty() ? "not set: " : "default of ") + std::string(s.command) + " " + s.option
                          : "not set: device commands refuse until --device names one";
    }
    std::printf("%-14s %-24s %s\n", s.key, value.c_str(), source.c_str());
  }
  return 0;
}

}  // namespace dg::host

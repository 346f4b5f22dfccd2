// The user's config file (`key = value` lines): which settings it may hold, reading it with its
// line numbers, and filling the options a command line left out.
#pragma once
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace dg::host {

// A setting the config file may hold: the option of which command it stands in for.
struct ConfigSetting {
  const char* key;
  const char* command;      // the subcommand whose option it fills; "" for the device (every device command)
  const char* option;       // that option's long name, e.g. "--feed"
  const char* overridden_by;  // options of that command that replace it when given ("" none), space separated
  const char* meaning;
  const char* also = "";    // other subcommands with the same option that it fills too, space separated
};

// Every setting, in the order `config show` prints them.
const std::vector<ConfigSetting>& config_settings();

struct ConfigEntry {
  std::string key, value;
  int line = 0;
};

// The file's settings (comments after '#', blank lines skipped). An empty list when there is no
// file. Throws std::invalid_argument naming path:line for a line that is not `key = value`, a key
// that is not a setting (a typo must not be ignored: `fed = 5` would scan at the default feed),
// an empty value or a key given twice.
std::vector<ConfigEntry> read_config(const std::string& path);

// Gives the chosen subcommand of `app` (already parsed) the config file's values for the options
// its command line left out, through the options' own validators. Throws std::invalid_argument
// naming path:line and the option when a value is refused.
void apply_config(CLI::App& app, const std::string& path);

}  // namespace dg::host

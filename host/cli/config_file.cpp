// Settings from ~/.config/digitizer/config fill only what the command line left out, and go
// through the same validators as the options they stand in for.
#include "host/cli/config_file.h"

#include <CLI/CLI.hpp>

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace dg::host {

namespace {

std::string trimmed(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

const ConfigSetting* find_setting(const std::string& key) {
  for (const ConfigSetting& s : config_settings()) {
    if (key == s.key) return &s;
  }
  return nullptr;
}

std::string known_keys() {
  std::string out;
  for (const ConfigSetting& s : config_settings()) out += std::string(out.empty() ? "" : ", ") + s.key;
  return out;
}

// Whether `name` is one of the space-separated words of `list`.
bool names(const char* list, const std::string& name) {
  std::istringstream words(list);
  for (std::string word; words >> word;) {
    if (word == name) return true;
  }
  return false;
}

bool given(const CLI::App& command, const std::string& long_name) {
  const CLI::Option* o = command.get_option_no_throw(long_name);
  return o != nullptr && o->count() > 0;
}

}  // namespace

const std::vector<ConfigSetting>& config_settings() {
  static const std::vector<ConfigSetting> settings = {
      {"device", "", "--device", "", "the device every device command talks to (after --device and DIGITIZER_DEVICE)"},
      {"feed", "scan", "--feed", "", "table speed between points, mm/s"},
      {"samples", "scan", "--samples", "", "gauge readings averaged per point"},
      {"settle_ms", "scan", "--settle-ms", "", "wait after each move before reading, ms"},
      {"settle_um", "scan", "--settle-um", "", "then read until two readings agree within this, um"},
      {"spread_um", "scan", "--spread-um", "", "a point's samples must agree within this, um"},
      {"approach", "scan", "--approach", "", "overshoot so every point is reached moving towards +x/+y, mm"},
      {"reference_every", "scan", "--reference-every", "", "read the first point again after every N lines, to remove drift"},
      {"repeatability", "scan", "--repeatability", "", "readings of the first point before a scan, for each point's uncertainty"},
      {"calibration", "scan", "--calibration", "", "the table calibration every scan is corrected by (digitizer calibrate); none: no correction",
       "status"},
      {"tolerance", "inspect", "--tolerance", "--upper --lower", "the part's profile tolerance +-MM that inspect decides"},
      {"bands", "inspect", "--band", "", "deviations inspect counts the points within, mm (a list)"},
      {"operator", "inspect", "--operator", "", "who measures, for the report"},
      {"company", "inspect", "--company", "", "for whom, for the report"},
  };
  return settings;
}

std::vector<ConfigEntry> read_config(const std::string& path) {
  std::vector<ConfigEntry> entries;
  std::ifstream in(path);
  std::string line;
  for (int number = 1; in && std::getline(in, line); ++number) {
    const std::string text = trimmed(line.substr(0, line.find('#')));
    if (text.empty()) continue;
    const std::string where = path + ":" + std::to_string(number) + ": ";
    const size_t equals = text.find('=');
    if (equals == std::string::npos) throw std::invalid_argument(where + "not a `key = value` line: " + text);
    ConfigEntry e{trimmed(text.substr(0, equals)), trimmed(text.substr(equals + 1)), number};
    if (!find_setting(e.key)) throw std::invalid_argument(where + "`" + e.key + "` is no setting (known: " + known_keys() + ")");
    if (e.value.empty()) throw std::invalid_argument(where + "`" + e.key + " =` gives no value");
    for (const ConfigEntry& earlier : entries) {
      if (earlier.key == e.key) {
        throw std::invalid_argument(where + "`" + e.key + "` is set again (first on line " + std::to_string(earlier.line) + ")");
      }
    }
    entries.push_back(e);
  }
  return entries;
}

void apply_config(CLI::App& app, const std::string& path) {
  const std::vector<ConfigEntry> entries = read_config(path);
  for (CLI::App* command : app.get_subcommands()) {
    for (const ConfigEntry& e : entries) {
      const ConfigSetting& s = *find_setting(e.key);
      if (command->get_name() != s.command && !names(s.also, command->get_name())) continue;
      if (given(*command, s.option)) continue;
      std::istringstream others(s.overridden_by);
      bool overridden = false;
      for (std::string other; others >> other;) overridden = overridden || given(*command, other);
      if (overridden) continue;
      CLI::Option* option = command->get_option_no_throw(s.option);
      if (!option) continue;
      try {
        std::string value = e.value;
        if (option->get_items_expected_max() > 1) {  // a list: commas or spaces between its values
          for (char& c : value) c = c == ',' ? ' ' : c;
          std::istringstream items(value);
          for (std::string item; items >> item;) option->add_result(item);
        } else {
          option->add_result(value);
        }
        option->run_callback();
      } catch (const CLI::Error& error) {
        throw std::invalid_argument(path + ":" + std::to_string(e.line) + ": " + e.key + " = " + e.value + " (for " +
                                    command->get_name() + " " + s.option + "): " + error.what());
      }
    }
  }
}

}  // namespace dg::host

// `digitizer config show`: the settings a command starts from, and where each came from.
#pragma once
#include <CLI/CLI.hpp>

namespace dg::host {

void add_config_command(CLI::App& app);

// Runs `config show` when it was chosen: 0; -1 when another command was.
int run_config_command(const CLI::App& app);

}  // namespace dg::host

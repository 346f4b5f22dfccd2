// What the digitizer command says about itself for installation: man pages and shell completion,
// made from the same command tree as --help so they cannot drift from it; and its version line.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

namespace dg::host {

// The version line: version, commit, protocol version and build type.
std::string version_text();

// A bash completion script for `app`: its subcommands, each one's options, device URI schemes
// after --device, and file names elsewhere.
std::string bash_completion(const CLI::App& app);
// The same for zsh (a #compdef function on _arguments, each option with its description).
std::string zsh_completion(const CLI::App& app);

// Writes digitizer.1 and digitizer-SUBCOMMAND.1 for each listed subcommand into `directory`
// (which must exist), each whole or not at all (host/io/atomic_file.h). Returns how many pages;
// throws std::runtime_error if a file cannot be written.
int write_man_pages(const CLI::App& app, const std::string& directory);

struct SelfDescriptionArgs {
  std::string shell = "bash";
  std::string output;  // completion: the file to write (standard output when empty)
  std::string directory;
};
// Adds the unlisted `completion [bash|zsh] [-o FILE]` and `manpages DIR` subcommands, which the build runs to
// make what it installs.
void add_self_description_commands(CLI::App& app, SelfDescriptionArgs& args);
// Runs whichever of them was given: its exit code, or -1 when neither was.
int run_self_description(const CLI::App& app, const SelfDescriptionArgs& args);

}  // namespace dg::host

// "-" as an output file: the data goes to standard output, everything the command says to standard error.
#pragma once
#include <string>

namespace dg::host {

// "-" (the command's default format) or "-.EXT" (the format EXT, e.g. "-.stl") names standard
// output. A file really called "-.stl" is written as "./-.stl".
bool is_standard_output(const std::string& path);

// For a command whose output is `path`: "-" becomes "-" + `default_extension` (".csv"), so the
// format is known; any other path is returned as it is.
std::string with_default_format(const std::string& path, const char* default_extension);

// How messages name an output: "standard output" for "-" or "-.EXT", else the path.
std::string output_name(const std::string& path);

// Keeps the real standard output for the data alone: from now on what the command prints (its
// summary, warnings) goes to standard error, and standard_output_fd() is where the data goes.
void reserve_standard_output_for_data();

// Where write_file_atomically writes a standard-output path (1 unless reserved).
int standard_output_fd();

}  // namespace dg::host

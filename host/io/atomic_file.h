// Writing a whole file so that a crash never leaves a half-written one under the real name.
#pragma once
#include <string>

namespace dg::host {

// Writes `bytes` to PATH.part and renames it into place. Throws std::runtime_error naming the file.
void write_file_atomically(const std::string& path, const std::string& bytes);

}  // namespace dg::host

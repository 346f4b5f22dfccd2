// Writing a whole output file so that a crash or a full disk never leaves a half-written one.
#pragma once
#include <string>

namespace dg::host {

// Writes a whole output file. A regular file (or none yet) is written to a hidden file beside it,
// synced and renamed into place: a failure (a full disk) leaves the old file or none, never a part
// or a truncated file. A symbolic link is followed: its target is written, the link stays. A
// device, pipe or socket is written through, never replaced. Throws std::runtime_error naming the
// path and the reason. "-" or "-.EXT" is standard output (host/io/standard_output.h).
void write_file_atomically(const std::string& path, const std::string& bytes);

}  // namespace dg::host

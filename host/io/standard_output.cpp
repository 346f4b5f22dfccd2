// Standard output as an output file: the data keeps the real descriptor, the rest is moved to standard error.
#include "host/io/standard_output.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace dg::host {

namespace {
int data_fd = STDOUT_FILENO;
}  // namespace

bool is_standard_output(const std::string& path) {
  if (path == "-") return true;
  return path.size() > 2 && path[0] == '-' && path[1] == '.' && path.find('/') == std::string::npos;
}

std::string with_default_format(const std::string& path, const char* default_extension) {
  return path == "-" ? std::string("-") + default_extension : path;
}

std::string output_name(const std::string& path) { return is_standard_output(path) ? "standard output" : path; }

void reserve_standard_output_for_data() {
  if (data_fd != STDOUT_FILENO) return;
  std::fflush(stdout);
  const int kept = ::fcntl(STDOUT_FILENO, F_DUPFD_CLOEXEC, 3);
  if (kept < 0 || ::dup2(STDERR_FILENO, STDOUT_FILENO) < 0) {
    throw std::runtime_error(std::string("standard output: cannot keep it for the data: ") + std::strerror(errno));
  }
  data_fd = kept;
}

int standard_output_fd() { return data_fd; }

}  // namespace dg::host

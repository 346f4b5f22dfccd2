// The running program's prefix, from /proc/self/exe.
#include "host/io/own_prefix.h"

#include <unistd.h>

#include <climits>

namespace dg::host {

std::string own_prefix() {
  char self[PATH_MAX] = {};
  const ssize_t n = readlink("/proc/self/exe", self, sizeof(self) - 1);
  if (n <= 0) return "";
  std::string path(self, static_cast<size_t>(n));
  path = path.substr(0, path.rfind('/'));  // .../bin
  return path.substr(0, path.rfind('/'));
}

}  // namespace dg::host

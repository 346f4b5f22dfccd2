// A PATH search of our own: posix_spawnp would search too, but the commands must say before
// starting anything whether the program is there at all.
#include "host/cli/program_path.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>

namespace dg::host {

std::string find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  const std::string directories = path ? path : "/usr/bin:/bin";
  size_t start = 0;
  while (start <= directories.size()) {
    const size_t end = std::min(directories.find(':', start), directories.size());
    const std::string candidate = directories.substr(start, end - start) + "/" + name;
    if (end > start && access(candidate.c_str(), X_OK) == 0) return candidate;
    start = end + 1;
  }
  return "";
}

}  // namespace dg::host

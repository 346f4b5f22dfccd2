// memory-probe: calls tune_memory as digitizer's main does and reports what the test of it reads.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include "host/parallel/memory_reuse.h"

int main(int argc, char** argv) {
  dg::host::tune_memory(argv);
  // The environment this image was started with: a restart's holds the tunables it set.
  std::ifstream environ_file("/proc/self/environ", std::ios::binary);
  const std::string started_with((std::istreambuf_iterator<char>(environ_file)), std::istreambuf_iterator<char>());
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  std::printf("tunables=%s\n", tunables ? tunables : "(unset)");
  std::printf("mark=%s\n", std::getenv("DIGITIZER_CALLER_TUNABLES") ? "left" : "gone");
  std::printf("restarted=%s\n", started_with.find("glibc.malloc.hugetlb=1") != std::string::npos ? "yes" : "no");
  for (int k = 1; k < argc; ++k) std::printf("arg=%s\n", argv[k]);
  return 0;
}

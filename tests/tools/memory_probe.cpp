// memory-probe: calls tune_memory as digitizer's main does and reports what the test of it reads.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include "host/parallel/memory_reuse.h"

int main(int argc, char** argv) {
  // As digitizer's filter does, given "per-thread" first.
  const bool per_thread = argc > 1 && std::string(argv[1]) == "per-thread";
  dg::host::tune_memory(argv, dg::host::Restart::kForLargeInput,
                        per_thread ? dg::host::Heaps::kPerThread : dg::host::Heaps::kShared);
  // The environment this image was started with: a restart's holds the tunables it set.
  std::ifstream environ_file("/proc/self/environ", std::ios::binary);
  const std::string started_with((std::istreambuf_iterator<char>(environ_file)), std::istreambuf_iterator<char>());
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  std::printf("tunables=%s\n", tunables ? tunables : "(unset)");
  std::printf("mark=%s\n", std::getenv("DIGITIZER_CALLER_TUNABLES") ? "left" : "gone");
  std::printf("restarted=%s\n", started_with.find("glibc.malloc.hugetlb=1") != std::string::npos ? "yes" : "no");
  // A block another thread allocates lies in the main thread's heap (within 4 GiB of one the main
  // thread allocates) only if every thread shares that heap; a thread's own heap is a mapping of its
  // own, far from it.
  if (dg::host::huge_pages_asked_for_by_restart()) {
    void* mine = std::malloc(65536);
    void* theirs = nullptr;
    std::thread([&] { theirs = std::malloc(65536); }).join();
    const long long apart = static_cast<long long>(reinterpret_cast<uintptr_t>(theirs)) -
                            static_cast<long long>(reinterpret_cast<uintptr_t>(mine));
    std::printf("heaps=%s\n", std::llabs(apart) < (1LL << 32) ? "one" : "several");
    std::free(theirs);
    std::free(mine);
  } else {
    std::printf("heaps=(not glibc's)\n");
  }
  for (int k = 1; k < argc; ++k) std::printf("arg=%s\n", argv[k]);
  return 0;
}

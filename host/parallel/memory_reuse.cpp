// glibc's allocator asked for huge pages and to keep freed blocks (memory_reuse.h).
#include "host/parallel/memory_reuse.h"

#include <cstdlib>
#include <cstring>
#include <string>

#if defined(__GLIBC__)
#include <malloc.h>
#include <sys/stat.h>
#include <unistd.h>
#endif

namespace dg::host {

namespace {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitized = true;  // the sanitizer's allocator, not glibc's
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

#if defined(__GLIBC__)
// Whether an argument names a regular file of at least kLargeInputBytes.
bool names_large_file(char** argv) {
  for (char** arg = argv + 1; *arg; ++arg) {
    struct stat st;
    if (stat(*arg, &st) == 0 && S_ISREG(st.st_mode) && st.st_size >= kLargeInputBytes) return true;
  }
  return false;
}
#endif

// Set in the restarted program, with the caller's own GLIBC_TUNABLES (or kUnset) to put back.
constexpr const char* kRestarted = "DIGITIZER_CALLER_TUNABLES";
constexpr const char* kUnset = "\x01";

#if defined(__GLIBC__)
// GLIBC_TUNABLES as the caller gave it (kUnset: it had none), and the mark gone.
void put_back_tunables(const char* caller) {
  if (std::strcmp(caller, kUnset) != 0) {
    setenv("GLIBC_TUNABLES", caller, 1);
  } else {
    unsetenv("GLIBC_TUNABLES");
  }
  unsetenv(kRestarted);
}
#endif

}  // namespace

void tune_memory(char** argv, Restart when, Heaps heaps) {
#if defined(__GLIBC__)
  if (const char* caller = std::getenv(kRestarted)) {
    // A copy: unsetting the mark may release the string getenv returned.
    const std::string saved = caller;
    put_back_tunables(saved.c_str());
    return;
  }
  // These kept by mallopt in any case: no block from a mapping of its own (a thread's arena still
  // maps one larger than its heaps), the heap's free top kept up to 1 GiB, and (Heaps::kShared) one
  // heap for every thread (memory_reuse.h).
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  const bool shared = heaps == Heaps::kShared;
  if (shared) mallopt(M_ARENA_MAX, 1);
  const char* wanted = std::getenv("DIGITIZER_HUGE_PAGES");
  if (!huge_pages_asked_for_by_restart() || argv == nullptr || argv[0] == nullptr ||
      (wanted && std::strcmp(wanted, "0") == 0) || (when == Restart::kForLargeInput && !names_large_file(argv))) {
    return;
  }
  // The caller's value, copied: setting the variable below may release the string getenv gave.
  const char* found = std::getenv("GLIBC_TUNABLES");
  const std::string caller = found ? found : kUnset;
  // The caller's own settings come last, so they win over these.
  std::string tunables = "glibc.malloc.hugetlb=1:glibc.malloc.mmap_max=0:glibc.malloc.trim_threshold=1073741824";
  if (shared) tunables += ":glibc.malloc.arena_max=1";
  if (found && *found) tunables += ":" + caller;
  if (setenv(kRestarted, caller.c_str(), 1) != 0 || setenv("GLIBC_TUNABLES", tunables.c_str(), 1) != 0) {
    put_back_tunables(caller.c_str());
    return;
  }
  execv("/proc/self/exe", argv);
  // Not restarted (no /proc, say): as it was, with freed blocks kept.
  put_back_tunables(caller.c_str());
#else
  (void)argv;
  (void)when;
  (void)heaps;
#endif
}

bool huge_pages_asked_for_by_restart() {
#if defined(__GLIBC__)
  return !kSanitized;
#else
  return false;
#endif
}

}  // namespace dg::host

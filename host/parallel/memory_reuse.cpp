// glibc's allocator told to keep large freed blocks (memory_reuse.h).
#include "host/parallel/memory_reuse.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace dg::host {

void keep_freed_memory() {
#if defined(__GLIBC__)
  // No block from its own mapping (a thread's arena still maps one larger than its heap can hold),
  // and the heap's free top kept up to 1 GiB.
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
}

}  // namespace dg::host

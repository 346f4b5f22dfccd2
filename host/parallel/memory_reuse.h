// Keeping freed memory in the process, so the next large vector reuses pages already mapped.
#pragma once

namespace dg::host {

// glibc hands every freed block above its mmap threshold back to the kernel, and every vector of
// a million points allocated after it faults its pages in again. On a virtual machine a fault is
// dear: on the 2-core benchmark machine touching fresh memory ran at about 0.4 GB/s, and page
// faults were 11 % of fit_bench's time. Called once at the start of a program, before its
// threads: large blocks come from the heap and freed ones stay there for the next. Peak memory
// is unchanged (fit_bench 224-232 MB either way); memory freed is not returned before exit, which
// suits a command that runs one job.
void keep_freed_memory();

}  // namespace dg::host

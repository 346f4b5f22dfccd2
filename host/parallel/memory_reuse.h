// Large memory on huge pages and freed memory kept in the process, so big vectors cost few page faults.
#pragma once

namespace dg::host {

// A page fault is dear on a virtual machine: on the 2-core benchmark machine fresh memory was
// touched at about 0.4 GB/s, and faults were 9 to 11 % of the LTS filter's and fit_bench's time.
// glibc can do three things about it, none by default:
//  - keep large freed blocks for the next allocation, instead of handing each back to the kernel
//    (every vector of a million points then faulted its pages in again);
//  - ask the kernel for transparent huge pages on its heaps (one fault per 2 MB, not per 4 kB),
//    which most distributions grant only to memory that asks (THP "madvise");
//  - keep one heap for every thread (arena_max 1). A worker thread's own heap kept what the
//    worker freed for that worker alone (the fit's per-slice sums, a sort's buffers: 30 to 60 MB
//    on a million points), where the main thread's later vectors faulted fresh pages in again,
//    and it got 4 kB pages: `fit` on the 1e6-point PLY took 10,400 faults and 0.73 s, with one
//    heap 830 faults and 0.58 s, its peak 185 MB -> 157 MB. Small blocks still come from each
//    thread's own cache (glibc's tcache), so the filter's many small ones do not wait on a lock
//    (`filter --lts` on grids and scattered points unchanged). Only the filter's judging of a grid
//    with outliers, which fills a block for every point from both threads, took 8 % longer in one
//    heap (1.73 s against 1.60 s); `filter` keeps a heap per thread (Heaps::kPerThread).
// The second is only a tunable read from GLIBC_TUNABLES at start-up, so the first call starts the
// program again (execv of /proc/self/exe, same arguments) with both set; the second run puts the
// caller's GLIBC_TUNABLES back before anything else, so programs it starts (the simulator, a
// browser) see the environment it was given. Where that cannot be done (no /proc, a sanitizer
// build, DIGITIZER_HUGE_PAGES=0), freed blocks are still kept, by mallopt.
// Peak memory moves by up to about 10 % from run to run with huge pages (`fit` on the 1e6-point PLY:
// 259-287 MB, against 256-277 MB before any of this).
// The restart costs a second start-up (about 8 ms for `digitizer`; 65 ms while it linked the CAD
// kernel, which is now a module loaded on use, cad_module.h), so by default it is made only for a
// large job: one of whose arguments names a file of at least kLargeInputBytes (the 1e5-point grid
// scan is 1.3 MB; its LTS filter gained 0.37 s).
// Call first in main(), before any thread starts.
enum class Restart { kForLargeInput, kAlways };
enum class Heaps { kShared, kPerThread };
constexpr long long kLargeInputBytes = 1 << 20;
void tune_memory(char** argv, Restart when = Restart::kForLargeInput, Heaps heaps = Heaps::kShared);

// Whether tune_memory restarts the program with huge pages asked for: a glibc build without a
// sanitizer (whose allocator replaces glibc's).
bool huge_pages_asked_for_by_restart();

}  // namespace dg::host

// Running a loop over [0, n) on every core of the machine: the host's one way to use both cores.
#pragma once
#include <cstddef>
#include <functional>

namespace dg::host {

// Worker threads a loop may use: the DIGITIZER_THREADS environment variable (1..256) when set, else
// the machine's cores (std::thread::hardware_concurrency), at least 1.
unsigned worker_count();

// Calls body(begin, end, worker) over chunks that cover [0, n) once each, on up to worker_count()
// threads (the caller's among them); `worker` (0..worker_count() - 1) tells a body which of its
// per-worker scratch buffers is its own. Loops shorter than 2 x min_chunk run on the caller alone.
// A body that throws: the other chunks still end, then the first exception is rethrown here.
// The body must not write what another index reads; results are then those of one thread.
void parallel_for(size_t n, const std::function<void(size_t begin, size_t end, unsigned worker)>& body,
                  size_t min_chunk = 256);

}  // namespace dg::host

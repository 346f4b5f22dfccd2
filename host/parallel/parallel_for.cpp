// Chunks handed out from an atomic counter, so a slow chunk (a crease's extra models, say) does not
// hold the other cores idle.
#include "host/parallel/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace dg::host {

unsigned worker_count() {
  if (const char* given = std::getenv("DIGITIZER_THREADS")) {
    char* end = nullptr;
    const long n = std::strtol(given, &end, 10);
    if (end != given && *end == '\0' && n >= 1 && n <= 256) return static_cast<unsigned>(n);
  }
  return std::max(1u, std::thread::hardware_concurrency());
}

void parallel_for(size_t n, const std::function<void(size_t, size_t, unsigned)>& body, size_t min_chunk) {
  if (n == 0) return;
  min_chunk = std::max<size_t>(1, min_chunk);
  const unsigned workers = static_cast<unsigned>(std::min<size_t>(worker_count(), n / min_chunk));
  if (workers <= 1) {
    body(0, n, 0);
    return;
  }
  // About eight chunks a worker: small enough to balance, large enough to cost nothing to hand out.
  const size_t chunk = std::max(min_chunk, n / (8 * static_cast<size_t>(workers)));
  std::atomic<size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_lock;
  auto work = [&](unsigned worker) {
    for (;;) {
      const size_t begin = next.fetch_add(chunk);
      if (begin >= n) return;
      try {
        body(begin, std::min(n, begin + chunk), worker);
      } catch (...) {
        const std::lock_guard<std::mutex> hold(failure_lock);
        if (!failure) failure = std::current_exception();
      }
    }
  };
  std::vector<std::thread> threads;
  threads.reserve(workers - 1);
  for (unsigned w = 1; w < workers; ++w) threads.emplace_back(work, w);
  work(0);
  for (std::thread& t : threads) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace dg::host

// Blocking writes give the simulated device the host's back-pressure; reads never block.
#include "hw/sim/fd_link.h"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>

namespace dg::sim {

FdLink::FdLink(int read_fd, int write_fd) : read_fd_(read_fd), write_fd_(write_fd) {
  const int flags = fcntl(read_fd_, F_GETFL);
  if (flags >= 0) fcntl(read_fd_, F_SETFL, flags | O_NONBLOCK);
}

size_t FdLink::write(const uint8_t* data, size_t size) {
  size_t done = 0;
  while (done < size && !closed_) {
    const ssize_t n = ::write(write_fd_, data + done, size - done);
    if (n > 0) {
      done += static_cast<size_t>(n);
    } else if (n < 0 && (errno == EINTR)) {
      continue;
    } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      pollfd p{write_fd_, POLLOUT, 0};
      ::poll(&p, 1, -1);
    } else {
      closed_ = true;
    }
  }
  // A closed link swallows bytes; wait() then reports shutdown.
  return size;
}

size_t FdLink::read(uint8_t* data, size_t capacity) {
  if (closed_) return 0;
  for (;;) {
    const ssize_t n = ::read(read_fd_, data, capacity);
    if (n > 0) return static_cast<size_t>(n);
    if (n == 0) {
      closed_ = true;
      return 0;
    }
    if (errno == EINTR) continue;
    if (errno != EAGAIN && errno != EWOULDBLOCK) closed_ = true;
    return 0;
  }
}

bool FdLink::wait_readable(int timeout_ms) {
  while (!closed_) {
    pollfd p{read_fd_, POLLIN, 0};
    const int r = ::poll(&p, 1, timeout_ms);
    if (r == 0) return false;  // the time ran out
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) {
      closed_ = true;
      break;
    }
    if (p.revents & (POLLIN | POLLHUP | POLLERR)) return true;
  }
  return false;
}

}  // namespace dg::sim

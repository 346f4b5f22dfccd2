// Reads wait with poll(2); writes take everything or throw, and never raise SIGPIPE.
#include "host/transport/fd_transport.h"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace dg::host {

FdTransport::~FdTransport() {
  if (fd_ >= 0) ::close(fd_);
}

void FdTransport::adopt(int fd) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = fd;
  heard_ = false;
}

void FdTransport::disconnect() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void FdTransport::write(const uint8_t* data, size_t size) {
  if (fd_ < 0) throw TransportError(uri_ + ": not connected");
  size_t done = 0;
  while (done < size) {
    const ssize_t n = send(fd_, data + done, size - done, MSG_NOSIGNAL);
    if (n > 0) {
      done += static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    throw TransportError(uri_ + ": write failed: " +
                         (errno == EPIPE || errno == ECONNRESET ? closed_reason() : std::strerror(errno)));
  }
}

size_t FdTransport::read(uint8_t* data, size_t capacity, int timeout_ms) {
  if (fd_ < 0) throw TransportError(uri_ + ": not connected");
  for (;;) {
    pollfd p{fd_, POLLIN, 0};
    const int r = poll(&p, 1, timeout_ms);
    if (r < 0 && errno == EINTR) return 0;  // a signal (Ctrl-C): let the caller look
    if (r < 0) throw TransportError(uri_ + ": poll failed: " + std::strerror(errno));
    if (r == 0) return 0;
    const ssize_t n = recv(fd_, data, capacity, 0);
    if (n > 0) {
      heard_ = true;
      return static_cast<size_t>(n);
    }
    if (n < 0 && errno == EINTR) continue;
    if (n == 0 || (n < 0 && errno == ECONNRESET)) throw TransportError(uri_ + ": " + closed_reason());
    throw TransportError(uri_ + ": read failed: " + std::strerror(errno));
  }
}

}  // namespace dg::host

// Connects with a 3 s limit, so an unplugged bench is an error message and not a hang.
#include "host/transport/socket_transport.h"

#include <cerrno>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace dg::host {

namespace {

// Why a one-host device (digitizer-sim --listen) turns a connection away.
constexpr const char* kAnotherHost = "another host is probably connected to it (a device serves one host at a time)";

constexpr int kConnectTimeoutMs = 3000;

// Connects a fresh socket to `address`; returns the descriptor or -1 with errno set.
int connect_with_timeout(int family, const sockaddr* address, socklen_t length) {
  const int fd = socket(family, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) return -1;
  if (connect(fd, address, length) != 0) {
    if (errno != EINPROGRESS) {
      const int saved = errno;
      close(fd);
      errno = saved;
      return -1;
    }
    pollfd p{fd, POLLOUT, 0};
    int r;
    do {
      r = poll(&p, 1, kConnectTimeoutMs);
    } while (r < 0 && errno == EINTR);
    int error = 0;
    socklen_t size = sizeof(error);
    if (r <= 0 || getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &size) != 0 || error != 0) {
      close(fd);
      errno = r == 0 ? ETIMEDOUT : (error != 0 ? error : errno);
      return -1;
    }
  }
  // Reads wait in poll(2); the descriptor itself blocks, so writes give back-pressure.
  fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  return fd;
}

}  // namespace

SocketTransport::SocketTransport(const std::string& uri) : FdTransport(uri) {
  signal(SIGPIPE, SIG_IGN);
  const size_t colon = uri.find(':');
  const std::string scheme = uri.substr(0, colon);
  const std::string rest = colon == std::string::npos ? "" : uri.substr(colon + 1);
  if (scheme == "unix") {
    unix_ = true;
    path_ = rest;
    if (path_.empty()) throw std::invalid_argument("device URI '" + uri + "': unix: needs a socket path");
    if (path_.size() >= sizeof(sockaddr_un{}.sun_path)) {
      throw std::invalid_argument("device URI '" + uri + "': socket path longer than " +
                                  std::to_string(sizeof(sockaddr_un{}.sun_path) - 1) + " bytes");
    }
  } else if (scheme == "tcp") {
    const size_t last = rest.rfind(':');
    if (last == std::string::npos || last == 0 || last + 1 == rest.size()) {
      throw std::invalid_argument("device URI '" + uri + "': tcp: needs HOST:PORT, e.g. tcp:localhost:5555");
    }
    host_ = rest.substr(0, last);
    port_ = rest.substr(last + 1);
    // [::1]:5555 style IPv6 literals.
    if (host_.size() > 2 && host_.front() == '[' && host_.back() == ']') host_ = host_.substr(1, host_.size() - 2);
  } else {
    throw std::invalid_argument("device URI '" + uri + "': not a unix: or tcp: URI");
  }
  adopt(connect_once());
}

int SocketTransport::connect_once() const {
  if (unix_) {
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::memcpy(address.sun_path, path_.c_str(), path_.size() + 1);
    const int fd = connect_with_timeout(AF_UNIX, reinterpret_cast<const sockaddr*>(&address), sizeof(address));
    if (fd < 0 && errno == EAGAIN) {
      // The listening device's queue of waiting connections is full: it is busy with its host
      // and has not looked at the queue (a one-host device such as digitizer-sim --listen).
      throw TransportError(uri_ + ": the device takes no connection now: " + kAnotherHost);
    }
    if (fd < 0) throw TransportError(uri_ + ": cannot connect: " + std::strerror(errno));
    return fd;
  }
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  const int status = getaddrinfo(host_.c_str(), port_.c_str(), &hints, &found);
  if (status != 0) throw TransportError(uri_ + ": cannot resolve: " + gai_strerror(status));
  std::string error = "no address";
  for (addrinfo* a = found; a != nullptr; a = a->ai_next) {
    const int fd = connect_with_timeout(a->ai_family, a->ai_addr, a->ai_addrlen);
    if (fd >= 0) {
      freeaddrinfo(found);
      // Frames are small and latency-bound (acknowledgements): no Nagle delay.
      const int one = 1;
      setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
      return fd;
    }
    error = std::strerror(errno);
  }
  freeaddrinfo(found);
  throw TransportError(uri_ + ": cannot connect: " + error);
}

std::string SocketTransport::closed_reason() {
  // A device that serves one host at a time (digitizer-sim --listen) turns another away by
  // closing the connection before a word.
  if (!heard_) return std::string("the device closed the link before answering: ") + kAnotherHost;
  return FdTransport::closed_reason();
}

void SocketTransport::reconnect() {
  disconnect();
  adopt(connect_once());
}

}  // namespace dg::host

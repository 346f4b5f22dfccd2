// While no host is connected, written bytes go nowhere (a pulled cable) and reads find nothing;
// the firmware's link layer resends once a host is back.
#include "hw/sim/listen_link.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace dg::sim {

namespace {

volatile sig_atomic_t g_stop = 0;

}  // namespace

void ListenLink::request_stop() { g_stop = 1; }

bool ListenLink::closed() const { return g_stop != 0 || listen_fd_ < 0; }

ListenLink::ListenLink(const std::string& where) {
  signal(SIGPIPE, SIG_IGN);
  if (where.rfind("unix:", 0) == 0) {
    unix_path_ = where.substr(5);
    sockaddr_un address{};
    if (unix_path_.empty() || unix_path_.size() >= sizeof(address.sun_path)) {
      error_ = "unix: needs a socket path shorter than " + std::to_string(sizeof(address.sun_path)) + " bytes";
      return;
    }
    address.sun_family = AF_UNIX;
    std::memcpy(address.sun_path, unix_path_.c_str(), unix_path_.size() + 1);
    listen_fd_ = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    unlink(unix_path_.c_str());  // a socket left by an earlier run
    if (listen_fd_ < 0 || bind(listen_fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0 ||
        listen(listen_fd_, 1) != 0) {
      error_ = "cannot listen on " + unix_path_ + ": " + std::strerror(errno);
      if (listen_fd_ >= 0) close(listen_fd_);
      listen_fd_ = -1;
    }
    return;
  }
  if (where.rfind("tcp:", 0) != 0) {
    error_ = "listen address '" + where + "' is neither unix:PATH nor tcp:[HOST:]PORT";
    return;
  }
  std::string host = "127.0.0.1", port = where.substr(4);
  const size_t colon = port.rfind(':');
  if (colon != std::string::npos) {
    host = port.substr(0, colon);
    port = port.substr(colon + 1);
  }
  char* end = nullptr;
  const long number = std::strtol(port.c_str(), &end, 10);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(number));
  if (port.empty() || *end != '\0' || number < 0 || number > 65535 || inet_pton(AF_INET, host.c_str(), &address.sin_addr) != 1) {
    error_ = "listen address '" + where + "': need tcp:[IPv4:]PORT";
    return;
  }
  listen_fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const int one = 1;
  if (listen_fd_ >= 0) setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  socklen_t size = sizeof(address);
  if (listen_fd_ < 0 || bind(listen_fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0 ||
      listen(listen_fd_, 1) != 0 || getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&address), &size) != 0) {
    error_ = "cannot listen on " + where + ": " + std::strerror(errno);
    if (listen_fd_ >= 0) close(listen_fd_);
    listen_fd_ = -1;
    return;
  }
  port_ = ntohs(address.sin_port);
}

ListenLink::~ListenLink() {
  drop_host();
  if (listen_fd_ < 0) return;
  close(listen_fd_);
  if (!unix_path_.empty()) unlink(unix_path_.c_str());
}

void ListenLink::drop_host() {
  if (host_fd_ >= 0) close(host_fd_);
  host_fd_ = -1;
}

void ListenLink::accept_host() {
  const int fd = accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
  if (fd < 0) return;
  // One host at a time, as a USB device's interface is claimed by one process: while the current
  // host is connected, another is turned away (closed at once) rather than taking the link over
  // in the middle of its scan. A host that died has closed its end (the kernel does that even for
  // kill -9), and then the newcomer replaces it.
  if (host_fd_ >= 0) {
    pollfd p{host_fd_, POLLRDHUP, 0};
    const bool gone = ::poll(&p, 1, 0) > 0 && (p.revents & (POLLRDHUP | POLLHUP | POLLERR)) != 0;
    if (!gone) {
      close(fd);
      return;
    }
  }
  drop_host();
  host_fd_ = fd;
  const int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));  // fails harmlessly on unix sockets
}

size_t ListenLink::write(const uint8_t* data, size_t size) {
  size_t done = 0;
  while (done < size && host_fd_ >= 0) {
    const ssize_t n = ::send(host_fd_, data + done, size - done, MSG_NOSIGNAL);
    if (n > 0) {
      done += static_cast<size_t>(n);
    } else if (n < 0 && errno == EINTR) {
      if (g_stop) break;
    } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      // The host is slow to read: wait (back-pressure), unless it is gone.
      pollfd p{host_fd_, POLLOUT, 0};
      if (::poll(&p, 1, 1000) == 0) continue;
    } else {
      drop_host();
    }
  }
  return size;  // bytes for a host that left are lost on the line, like on a pulled cable
}

size_t ListenLink::read(uint8_t* data, size_t capacity) {
  // A busy device reads without waiting: look at the queue of new connections here too, so that
  // another host is turned away (or replaces a dead one) at once and not when the scan idles.
  pollfd p{listen_fd_, POLLIN, 0};
  if (listen_fd_ >= 0 && ::poll(&p, 1, 0) > 0 && (p.revents & POLLIN) != 0) accept_host();
  if (host_fd_ < 0) return 0;
  for (;;) {
    const ssize_t n = ::recv(host_fd_, data, capacity, 0);
    if (n > 0) return static_cast<size_t>(n);
    if (n < 0 && errno == EINTR) continue;
    if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) drop_host();
    return 0;
  }
}

bool ListenLink::wait_readable(int timeout_ms) {
  while (!closed()) {
    pollfd p[2] = {{listen_fd_, POLLIN, 0}, {host_fd_, POLLIN, 0}};
    const int r = ::poll(p, host_fd_ >= 0 ? 2 : 1, timeout_ms);
    if (r == 0) return false;
    if (r < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    if (p[0].revents & POLLIN) {
      accept_host();
      return true;
    }
    if (p[1].revents & (POLLIN | POLLHUP | POLLERR)) return true;
  }
  return false;
}

}  // namespace dg::sim

// LinkPort that waits for hosts on a unix or TCP socket, one at a time, so the simulated device
// outlives them: a host that dies or pulls the cable leaves the scan running (or paused) for the
// next one, as a real device on USB does.
#pragma once
#include <string>

#include "hw/sim/sim_board.h"

namespace dg::sim {

class ListenLink final : public LinkPort {
 public:
  // `where` is "unix:PATH" or "tcp:[HOST:]PORT" (HOST defaults to 127.0.0.1). On failure
  // listening() is false and error() says why.
  explicit ListenLink(const std::string& where);
  ~ListenLink() override;
  ListenLink(const ListenLink&) = delete;
  ListenLink& operator=(const ListenLink&) = delete;

  bool listening() const { return listen_fd_ >= 0; }
  const std::string& error() const { return error_; }
  // The TCP port actually bound (for tcp:0), or 0.
  int port() const { return port_; }

  size_t write(const uint8_t* data, size_t size) override;
  size_t read(uint8_t* data, size_t capacity) override;
  bool wait_readable(int timeout_ms = -1) override;
  // Only a stop request (SIGTERM, SIGINT) closes it; a host leaving does not.
  bool closed() const override;
  // Asks the link to close (safe from a signal handler).
  static void request_stop();

 private:
  void accept_host();
  void drop_host();

  int listen_fd_ = -1;
  int host_fd_ = -1;
  std::string unix_path_;
  std::string error_;
  int port_ = 0;
};

}  // namespace dg::sim

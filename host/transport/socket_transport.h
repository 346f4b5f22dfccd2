// unix:PATH and tcp:HOST:PORT: a device behind a socket (the QEMU UART bridge, a remote bench,
// a digitizer-sim --listen). The device outlives the connection, so the link can reconnect.
#pragma once
#include <string>

#include "host/transport/fd_transport.h"

namespace dg::host {

class SocketTransport final : public FdTransport {
 public:
  // `uri` is "unix:PATH" or "tcp:HOST:PORT"; connects at once (TransportError when it cannot).
  explicit SocketTransport(const std::string& uri);
  bool reconnectable() const override { return true; }
  void reconnect() override;

 protected:
  std::string closed_reason() override;

 private:
  int connect_once() const;
  bool unix_ = false;
  std::string path_;         // unix:
  std::string host_, port_;  // tcp:
};

}  // namespace dg::host

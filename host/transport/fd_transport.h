// A transport over a connected stream file descriptor (socket pair, unix or TCP socket).
#pragma once
#include <string>

#include "host/transport/transport.h"

namespace dg::host {

class FdTransport : public Transport {
 public:
  ~FdTransport() override;
  FdTransport(const FdTransport&) = delete;
  FdTransport& operator=(const FdTransport&) = delete;

  void write(const uint8_t* data, size_t size) override;
  size_t read(uint8_t* data, size_t capacity, int timeout_ms) override;
  std::string describe() const override { return uri_; }
  void disconnect() override;

 protected:
  explicit FdTransport(std::string uri) : uri_(std::move(uri)) {}
  // Why the other end closed, for the error message.
  virtual std::string closed_reason() { return "the device closed the link"; }
  // Takes ownership of a connected descriptor (closing any previous one).
  void adopt(int fd);

  std::string uri_;
  int fd_ = -1;
  bool heard_ = false;  // a byte arrived on this connection
};

}  // namespace dg::host

// A byte stream to the host that a board's link is built on (a socket, a UART, FunctionFS, memory in
// tests): an interface of the HAL, so a board implements it without including the simulator.
#pragma once
#include <cstddef>
#include <cstdint>

namespace dg::hal {

class LinkPort {
 public:
  virtual ~LinkPort() = default;
  virtual size_t write(const uint8_t* data, size_t size) = 0;  // takes all unless closed
  virtual size_t read(uint8_t* data, size_t capacity) = 0;      // non-blocking
  // Blocks until the host has written something (true), the time runs out or the link closed
  // (false); timeout_ms < 0 waits without end.
  virtual bool wait_readable(int timeout_ms = -1) = 0;
  virtual bool closed() const = 0;
};

}  // namespace dg::hal

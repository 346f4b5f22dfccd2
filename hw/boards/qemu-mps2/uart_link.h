// The link to the host on the CMSDK APB UART0 of QEMU's mps2-an386 (bridged by QEMU to a socket):
// polled, no interrupts, bytes in and out through the data register.
#pragma once
#include "firmware/hal/link_port.h"

namespace dg::board {

class UartLink final : public hal::LinkPort {
 public:
  UartLink();
  size_t write(const uint8_t* data, size_t size) override;
  size_t read(uint8_t* data, size_t capacity) override;
  bool wait_readable(int timeout_ms = -1) override;
  bool closed() const override { return false; }
};

}  // namespace dg::board

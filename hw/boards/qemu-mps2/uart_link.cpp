// CMSDK APB UART (Arm DDI0479C): DATA at +0, STATE at +4 (bit 0 TX buffer full, bit 1 RX buffer
// full), CTRL at +8 (bit 0 TX enable, bit 1 RX enable), BAUDDIV at +0x10 (at least 16).
#include "hw/boards/qemu-mps2/uart_link.h"

namespace dg::board {

namespace {

volatile uint32_t* const kUart0 = reinterpret_cast<volatile uint32_t*>(0x40004000);
constexpr uint32_t kTxFull = 1u << 0, kRxFull = 1u << 1;

bool rx_ready() { return (kUart0[1] & kRxFull) != 0; }

}  // namespace

UartLink::UartLink() {
  kUart0[4] = 217;  // 25 MHz / 115200: QEMU ignores the rate but wants a divider of 16 or more
  kUart0[2] = 3;    // TX and RX enabled
}

size_t UartLink::write(const uint8_t* data, size_t size) {
  for (size_t i = 0; i < size; ++i) {
    while ((kUart0[1] & kTxFull) != 0) {
    }
    kUart0[0] = data[i];
  }
  return size;
}

size_t UartLink::read(uint8_t* data, size_t capacity) {
  size_t n = 0;
  while (n < capacity && rx_ready()) data[n++] = static_cast<uint8_t>(kUart0[0]);
  return n;
}

bool UartLink::wait_readable(int timeout_ms) {
  // Polls; a millisecond is about 25,000 rounds of this loop under -icount shift=0 (one
  // instruction a nanosecond, some 40 a round), which is all the timeout needs to be.
  const uint64_t rounds = timeout_ms < 0 ? UINT64_MAX : static_cast<uint64_t>(timeout_ms) * 25000;
  for (uint64_t i = 0; i < rounds; ++i) {
    if (rx_ready()) return true;
  }
  return false;
}

}  // namespace dg::board

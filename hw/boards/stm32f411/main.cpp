// The device firmware on a WeAct "Black Pill" STM32F411CEU6: the firmware core on real steppers,
// switches and gauge, its link on USB full speed. Pin map and wiring: docs/hardware.md.
#include <new>

#include "firmware/core/device.h"
#include "hw/boards/cortex-m/runtime.h"
#include "hw/boards/stm32f411/board.h"
#include "hw/boards/stm32f411/clock.h"
#include "hw/boards/stm32f411/interrupts.h"
#include "hw/boards/stm32f411/otg_fs.h"
#include "hw/boards/stm32f411/pins.h"
#include "hw/boards/stm32f411/registers.h"

namespace dg::stm32 {

InterruptTargets interrupts;

[[noreturn]] void fatal_stop() {
  asm volatile("cpsid i" ::: "memory");
  reg(kTim2 + kTimDier) = 0;                            // no more steps
  reg(kDriverEnablePort + kBsrr) = 1u << kDriverEnablePin;  // drivers off (enable is active low)
  reg(kScbAircr) = (0x05FAu << 16) | (1u << 2);          // SYSRESETREQ
  for (;;) {
  }
}

}  // namespace dg::stm32

namespace {

// The serial number is the chip's 96-bit unique ID in hex, so two controllers on one host can be
// told apart (`usb:serial=...`).
char serial[25] = {};

void make_serial() {
  constexpr char kHex[] = "0123456789ABCDEF";
  for (int word = 0; word < 3; ++word) {
    const uint32_t id = dg::stm32::reg(dg::stm32::kUniqueId + 4 * word);
    for (int nibble = 0; nibble < 8; ++nibble) serial[word * 8 + nibble] = kHex[(id >> (28 - 4 * nibble)) & 0xF];
  }
}

// Static storage built in place: the image registers no destructors and has no heap.
alignas(dg::stm32::OtgFsDevice) unsigned char usb_storage[sizeof(dg::stm32::OtgFsDevice)];
alignas(dg::stm32::Stm32Board) unsigned char board_storage[sizeof(dg::stm32::Stm32Board)];
alignas(dg::Device) unsigned char device_storage[sizeof(dg::Device)];

}  // namespace

int main() {
  const bool crystal_ok = dg::stm32::configure_clocks();
  make_serial();
  auto* usb = new (usb_storage) dg::stm32::OtgFsDevice(serial);
  auto* board = new (board_storage) dg::stm32::Stm32Board(*usb);
  dg::stm32::interrupts = {board, usb};
  board->start();

  dg::DeviceConfig config = dg::hardware_device_config(DIGITIZER_STM32_CALIPER != 0);
  config.device_id = serial;
  config.board = crystal_ok ? "stm32f411-blackpill" : "stm32f411-blackpill (no crystal: HSI clock)";
  config.stack_used_bytes = dg::cortex_m::stack_used_bytes;
  config.stack_size_bytes = dg::cortex_m::stack_size_bytes();
  auto* device = new (device_storage) dg::Device(*board, config);
  // A USB core that does not answer its bounded waits leaves the board without a link: restart
  // (the host, if any, sees no device; `status` after a good start says "software").
  if (!usb->start()) dg::stm32::fatal_stop();
  device->run();
  dg::stm32::fatal_stop();
}

// What the interrupt handlers reach: the board and the USB device main() built, and the stop that
// every fault ends in.
#pragma once

#include "hw/boards/stm32f411/board.h"
#include "hw/boards/stm32f411/otg_fs.h"

namespace dg::stm32 {

struct InterruptTargets {
  Stm32Board* board = nullptr;
  OtgFsDevice* usb = nullptr;
};
extern InterruptTargets interrupts;

// Disables the stepper drivers, then resets the chip.
[[noreturn]] void fatal_stop();

}  // namespace dg::stm32

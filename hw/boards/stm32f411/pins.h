// The Black Pill's pin map: which port pin each logical HAL pin is, and its electrical polarity.
// docs/hardware.md has the same table with the wiring.
#pragma once
#include <cstdint>

#include "firmware/hal/board.h"

namespace dg::stm32 {

struct PinMap {
  uint32_t port;   // GPIO port base address
  uint8_t number;  // 0-15; also the EXTI line of an edge input
  bool output;
  bool active_low;  // logical true = electrical low
  uint8_t pull;     // PUPDR: 0 none, 1 pull-up, 2 pull-down
};

const PinMap& pin_map(hal::Pin pin);

// Outputs that are not HAL pins: the stepper drivers' shared enable (active low) and the LED.
constexpr uint32_t kDriverEnablePort = 0x40020400;  // PB5
constexpr uint8_t kDriverEnablePin = 5;
constexpr uint32_t kLedPort = 0x40020800;  // PC13, lit when low
constexpr uint8_t kLedPin = 13;

}  // namespace dg::stm32

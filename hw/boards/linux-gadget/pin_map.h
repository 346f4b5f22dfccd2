// Which GPIO line carries each of the firmware's pins on a Linux-gadget board: the reference
// Raspberry Pi wiring (docs/hardware.md) and the --pin KEY=LINE changes to it.
#pragma once
#include <string>

#include "firmware/hal/board.h"
#include "hw/gpio/gpio_line.h"

namespace dg::gadget {

constexpr int kPinCount = static_cast<int>(hal::Pin::kCount);

struct PinMap {
  gpio::LineSpec pins[kPinCount];
  bool wired[kPinCount] = {};
  gpio::LineSpec driver_enable;  // held active while the program runs (the drivers' EN)
  bool enable_wired = false;
};

// The reference wiring on a Raspberry Pi's 40-pin header (BCM line names), as docs/hardware.md.
PinMap raspberry_pi_pins();
// The logical pin for a pin-map key ("step_x", "limit_y", "enable", ...): false if unknown.
bool pin_key(const std::string& key, int* pin);
// Applies "key=LINE" to the map; false with the reason.
bool apply_pin(const std::string& pair, PinMap* map, std::string* error);

}  // namespace dg::gadget

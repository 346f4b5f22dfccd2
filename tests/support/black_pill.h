// The Black Pill on the register-level fake of its chip: the board's own code, its interrupts wired
// as startup.cpp's vector table wires them, and a record of every output pin's changes.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "hw/boards/stm32f411/board.h"
#include "hw/boards/stm32f411/pins.h"
#include "hw/boards/stm32f411/registers.h"
#include "tests/support/fake_stm32.h"

namespace dg::test {
struct BlackPill {
  FakeStm32 chip;
  dg::stm32::OtgFsDevice usb{"TEST"};
  dg::stm32::Stm32Board board{usb};
  std::vector<FakeStm32::PinChange> outputs;
  std::function<void(const FakeStm32::PinChange&)> watch;  // the machine's side of the outputs

  explicit BlackPill(uint32_t reset_flags = 0) {
    chip.set_reset_flags(reset_flags);
    chip.set_handler(dg::stm32::kIrqTim2, [this] { board.step_timer_irq(); });
    chip.set_handler(dg::stm32::kIrqTim5, [this] { board.clock_irq(); });
    for (uint32_t line = 0; line <= 4; ++line) {
      chip.set_handler(dg::stm32::kIrqExti0 + static_cast<int>(line), [this, line] { board.edge_irq(line, line); });
    }
    chip.set_handler(dg::stm32::kIrqExti9_5, [this] { board.edge_irq(5, 9); });
    chip.set_handler(dg::stm32::kIrqExti15_10, [this] { board.edge_irq(10, 15); });
    chip.on_output = [this](const FakeStm32::PinChange& c) {
      outputs.push_back(c);
      if (watch) watch(c);
    };
    board.start();
  }
  void drive(hal::Pin pin, bool electrically_high) {
    const dg::stm32::PinMap& p = dg::stm32::pin_map(pin);
    chip.drive(p.port, p.number, electrically_high);
  }
  // The cycles at which `pin` went electrically high.
  std::vector<uint64_t> rises(hal::Pin pin) const {
    const dg::stm32::PinMap& p = dg::stm32::pin_map(pin);
    std::vector<uint64_t> at;
    for (const FakeStm32::PinChange& c : outputs) {
      if (c.port == p.port && c.pin == p.number && c.high) at.push_back(c.cycle);
    }
    return at;
  }
  bool drivers_enabled() const { return !chip.output_high(dg::stm32::kDriverEnablePort, dg::stm32::kDriverEnablePin); }
  // When the drivers' enable line (active low) was first driven high at or after `cycle`; 0: never.
  uint64_t drivers_cut_at(uint64_t cycle) const {
    for (const FakeStm32::PinChange& c : outputs) {
      if (c.port == dg::stm32::kDriverEnablePort && c.pin == dg::stm32::kDriverEnablePin && c.high && c.cycle >= cycle) {
        return c.cycle;
      }
    }
    return 0;
  }
};

}  // namespace dg::test

// Start-up and the vector table of the STM32F411: data and bss, the FPU, constructors, then main
// (which sets the clocks); each interrupt the board uses goes to its handler, every other one to a safe stop.
#include <cstdint>

#include "hw/boards/cortex-m/runtime.h"
#include "hw/boards/stm32f411/interrupts.h"
#include "hw/boards/stm32f411/registers.h"

extern "C" {
int main();

[[noreturn]] void reset_handler() {
  dg::cortex_m::paint_stack();
  dg::cortex_m::init_memory_and_fpu();
  dg::cortex_m::run_constructors();
  main();
  dg::stm32::fatal_stop();
}

// A fault, or an interrupt nobody enabled: stop the motors, then restart. The host sees the
// device leave and come back; a resume then reports that the scan is gone.
[[noreturn]] void fault_handler() { dg::stm32::fatal_stop(); }

void tim2_handler() { dg::stm32::interrupts.board->step_timer_irq(); }
void tim5_handler() { dg::stm32::interrupts.board->clock_irq(); }
void otg_fs_handler() { dg::stm32::interrupts.usb->irq(); }
void exti0_handler() { dg::stm32::interrupts.board->edge_irq(0, 0); }
void exti1_handler() { dg::stm32::interrupts.board->edge_irq(1, 1); }
void exti2_handler() { dg::stm32::interrupts.board->edge_irq(2, 2); }
void exti3_handler() { dg::stm32::interrupts.board->edge_irq(3, 3); }
void exti4_handler() { dg::stm32::interrupts.board->edge_irq(4, 4); }
void exti9_5_handler() { dg::stm32::interrupts.board->edge_irq(5, 9); }
void exti15_10_handler() { dg::stm32::interrupts.board->edge_irq(10, 15); }
}

namespace {

using Handler = void (*)();

struct VectorTable {
  const void* stack;
  Handler entries[15 + dg::stm32::kIrqCount];
};

constexpr VectorTable make_vectors() {
  VectorTable t{&__stack_top, {}};
  for (auto& e : t.entries) e = fault_handler;
  t.entries[0] = reset_handler;
  auto irq = [&t](int n, Handler h) { t.entries[15 + n] = h; };
  irq(dg::stm32::kIrqTim2, tim2_handler);
  irq(dg::stm32::kIrqTim5, tim5_handler);
  irq(dg::stm32::kIrqOtgFs, otg_fs_handler);
  irq(dg::stm32::kIrqExti0, exti0_handler);
  irq(dg::stm32::kIrqExti1, exti1_handler);
  irq(dg::stm32::kIrqExti2, exti2_handler);
  irq(dg::stm32::kIrqExti3, exti3_handler);
  irq(dg::stm32::kIrqExti4, exti4_handler);
  irq(dg::stm32::kIrqExti9_5, exti9_5_handler);
  irq(dg::stm32::kIrqExti15_10, exti15_10_handler);
  return t;
}

}  // namespace

__attribute__((section(".vectors"), used)) const VectorTable vectors = make_vectors();

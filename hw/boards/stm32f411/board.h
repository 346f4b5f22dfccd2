// The firmware's HAL on the STM32F411 "Black Pill": GPIO pins, EXTI edges, TIM2 as the step
// timer, TIM5 as the microsecond clock, the USB bulk link, and sleep until an interrupt.
#pragma once
#include <cstdint>

#include "firmware/hal/board.h"
#include "hw/boards/stm32f411/otg_fs.h"

namespace dg::stm32 {

class Stm32Board final : public hal::Board {
 public:
  explicit Stm32Board(OtgFsDevice& usb);

  // Pins, timers and the drivers' enable; call once after the clocks are set.
  void start();

  void write_pin(hal::Pin pin, bool level) override;
  bool read_pin(hal::Pin pin) override;
  void enable_drivers(bool on) override;
  void on_rising_edge(hal::Pin pin, hal::EdgeHandler handler, void* context) override;
  void start_step_timer(uint32_t delay_ns, hal::TimerHandler handler, void* context) override;
  void stop_step_timer() override;
  uint64_t now_us() override;
  // On the cycle counter: the e-stop's edge interrupt waits its 20 us confirming read with it, while
  // the step timer's interrupt, which outranks it, keeps stepping.
  void spin_ns(uint32_t ns) override;
  size_t link_write(const uint8_t* data, size_t size) override;
  size_t link_read(uint8_t* data, size_t capacity) override;
  bool link_suspended() override { return usb_.suspended(); }
  bool wait(uint64_t deadline_us) override;
  void watchdog_start(uint32_t timeout_ms) override;
  void watchdog_kick() override;
  hal::ResetCause reset_cause() override { return reset_cause_; }

  // Interrupt entry points (startup.cpp).
  void step_timer_irq();
  void clock_irq();
  void edge_irq(uint32_t first_line, uint32_t last_line);

 private:
  // Timer ticks for `delay_ns`, carrying the fraction so long chains of steps do not drift.
  uint32_t ticks_for(uint32_t delay_ns);

  OtgFsDevice& usb_;
  hal::TimerHandler step_handler_ = nullptr;
  void* step_context_ = nullptr;
  uint32_t tick_remainder_ = 0;  // in 1/125 of a tick
  struct Edge {
    hal::EdgeHandler handler = nullptr;
    void* context = nullptr;
  };
  Edge edges_[16];  // by EXTI line
  volatile uint32_t clock_high_ = 0;  // TIM5 wraps every 71.6 minutes; this counts the wraps
  uint32_t step_high_cycles_[2] = {};  // DWT cycle count when each STEP line went high
  hal::ResetCause reset_cause_ = hal::ResetCause::kUnknown;  // from RCC_CSR at start(), then cleared
};

}  // namespace dg::stm32

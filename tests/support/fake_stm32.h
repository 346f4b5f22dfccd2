// A register-level fake of the STM32F411 peripherals the Black Pill board uses (GPIO A-C, EXTI and
// SYSCFG, TIM2 and TIM5, the DWT cycle counter, RCC_CSR, the independent watchdog, the NVIC and
// PRIMASK), so that the board's own code runs on the host: QEMU's STM32F4 machines model neither
// the GPIO ports nor a timer's compare match (docs/hardware.md).
//
// Time is the core's cycle count at 96 MHz. Every register access takes kAccessCycles; between two
// accesses the fake delivers any interrupt that is pending, enabled, unmasked and of a higher
// priority than the one running, the way the NVIC takes an interrupt between two instructions. So a
// pin that changes at a given cycle interrupts the board's code exactly between the two accesses
// around that cycle, and a test can move the moment across every access of a routine.
#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <vector>

namespace dg::test {

class FakeStm32 {
 public:
  static constexpr uint32_t kCoreHz = 96000000;
  static constexpr uint64_t kAccessCycles = 2;     // one register access on the bus
  static constexpr uint64_t kEntryCycles = 12;     // Cortex-M4 interrupt entry (stacking)

  // Installs itself as the board code's register bus; one at a time.
  FakeStm32();
  ~FakeStm32();
  FakeStm32(const FakeStm32&) = delete;
  FakeStm32& operator=(const FakeStm32&) = delete;

  // The vector table: what runs for interrupt number `irq` (RM0383 table 37).
  void set_handler(int irq, std::function<void()> handler);

  uint64_t cycles() const { return now_; }
  // The main thread spins (or runs code that touches no register) for `cycles`: events and
  // interrupts fall due on the way.
  void run_for(uint64_t cycles);
  // Calls `event` when the clock reaches `cycle` (at once if it has), between two accesses.
  void at(uint64_t cycle, std::function<void()> event);

  // The world outside the pins. An input pin reads what drives it, else its pull (none reads low).
  void drive(uint32_t port, int pin, bool high);
  void release(uint32_t port, int pin);
  bool output_high(uint32_t port, int pin) const;
  uint32_t mode(uint32_t port, int pin) const;  // MODER: 0 input, 1 output
  uint32_t pull(uint32_t port, int pin) const;  // PUPDR: 0 none, 1 up, 2 down
  // Each change of an output pin, as it happens.
  struct PinChange {
    uint32_t port;
    int pin;
    bool high;
    uint64_t cycle;
  };
  std::function<void(const PinChange&)> on_output;

  // Sets the timer's counter as if it had run there (TIM5 near its wrap, say).
  void set_counter(uint32_t timer, uint32_t value);
  // The reset flags RCC_CSR holds at power-up (RMVF clears them).
  void set_reset_flags(uint32_t flags) { csr_ = flags; }
  bool watchdog_fired() const { return watchdog_fired_; }
  bool reset_requested() const { return reset_requested_; }
  int deepest_nesting() const { return deepest_nesting_; }

  // The bus (register_bus.h).
  uint32_t read(uint32_t address);
  void write(uint32_t address, uint32_t value);
  void write_byte(uint32_t address, uint8_t value);
  uint32_t primask() const { return primask_; }
  void set_primask(uint32_t value);
  void wait_for_interrupt();

 private:
  struct Timer {
    uint32_t cr1 = 0, dier = 0, sr = 0, psc = 0, active_psc = 0, ccr1 = 0;
    uint64_t base_cycle = 0;  // when `base_ticks` was the count
    uint64_t base_ticks = 0;  // ticks since start, unwrapped
    uint64_t ticks(uint64_t cycle) const { return base_ticks + ((cr1 & 1u) ? (cycle - base_cycle) / (active_psc + 1) : 0); }
  };
  struct Port {
    uint32_t moder = 0, ospeedr = 0, pupdr = 0, odr = 0, driven = 0, level = 0;
  };
  Timer* timer_at(uint32_t address, uint32_t& offset);
  Port* port_at(uint32_t address, uint32_t& offset);
  uint32_t input_levels(const Port& p) const;
  void set_odr(uint32_t port_base, Port& p, uint32_t odr);
  void input_changed(uint32_t port_base, uint32_t before, uint32_t after);
  // The next cycle after now_ at which a timer, the watchdog or a scheduled event needs attention.
  uint64_t next_event() const;
  void advance_to(uint64_t cycle, bool deliver_between);
  void step_to(uint64_t cycle);  // timers' flags and the watchdog up to `cycle`, no delivery
  void access();                 // one bus access's time; interrupts due are taken after it
  uint32_t value_at(uint32_t address);
  bool pending(int irq) const;
  void deliver();

  uint64_t now_ = 0;
  uint32_t primask_ = 0;
  std::vector<int> active_priorities_;  // of the handlers running, innermost last
  int deepest_nesting_ = 0;
  bool in_delivery_step_ = false;  // entering a handler or inside an access: nothing is taken
  std::map<int, std::function<void()>> handlers_;
  std::multimap<uint64_t, std::function<void()>> events_;
  std::map<uint32_t, uint32_t> plain_;  // registers with no side effects, by address
  uint32_t nvic_enabled_[3] = {};
  uint8_t nvic_priority_[96] = {};
  Port ports_[3];
  Timer tim2_, tim5_;
  uint32_t exti_imr_ = 0, exti_rtsr_ = 0, exti_ftsr_ = 0, exti_pr_ = 0;
  uint32_t exticr_[4] = {};
  uint32_t dwt_ctrl_ = 0;
  uint64_t dwt_base_ = 0;  // the cycle at which CYCCNT read 0
  uint32_t csr_ = 0;
  bool iwdg_running_ = false, iwdg_unlocked_ = false, watchdog_fired_ = false, reset_requested_ = false;
  uint32_t iwdg_pr_ = 0, iwdg_rlr_ = 0xFFF;
  uint64_t iwdg_kicked_ = 0;
};

}  // namespace dg::test

// Timing: TIM2 free-runs at 96 MHz and each step interrupt sets the next compare from the last
// one, not from "now", so interrupt latency never accumulates; a tick later than 1 us sets it from
// itself instead, so a late step stretches the move rather than bursting the steps it missed. STEP pulses are held high for
// kStepPulseNs (DRV8825 needs 1.9 us, A4988 1 us, TMC2209 100 ns), measured on the DWT cycle counter.
#include "hw/boards/stm32f411/board.h"

#include "firmware/hal/step_schedule.h"
#include "hw/boards/stm32f411/pins.h"
#include "hw/boards/stm32f411/registers.h"

namespace dg::stm32 {

namespace {

constexpr uint32_t kStepPulseNs = 2000;
constexpr uint32_t kStepPulseCycles = kStepPulseNs * (kSysclkHz / 1000000) / 1000;
constexpr uint32_t kLateStepTicks = kTimerClockHz / 1000000;  // 1 us of TIM2

void configure_pin(const PinMap& p) {
  const uint32_t shift2 = 2u * p.number;
  reg(p.port + kPupdr) = (reg(p.port + kPupdr) & ~(3u << shift2)) | (uint32_t{p.pull} << shift2);
  if (p.output) {
    reg(p.port + kBsrr) = 1u << (p.number + (p.active_low ? 0 : 16));  // start de-asserted
    reg(p.port + kOspeedr) |= 2u << shift2;                              // fast edges for STEP
  }
  reg(p.port + kModer) = (reg(p.port + kModer) & ~(3u << shift2)) | (uint32_t{p.output ? 1u : 0u} << shift2);
}

Irq exti_irq(uint32_t line) {
  if (line <= 4) return static_cast<Irq>(kIrqExti0 + line);
  return line <= 9 ? kIrqExti9_5 : kIrqExti15_10;
}

}  // namespace

Stm32Board::Stm32Board(OtgFsDevice& usb) : usb_(usb) {}

void Stm32Board::start() {
  // Why the chip last started: a power-on sets the pin and brown-out flags too, so the causes are
  // read from the most telling down; the flags stay until cleared.
  const uint32_t csr = reg(kRccCsr);
  reset_cause_ = (csr & (kCsrIwdgRstf | kCsrWwdgRstf)) ? hal::ResetCause::kWatchdog
                 : (csr & kCsrSftRstf)                 ? hal::ResetCause::kSoftware
                 : (csr & kCsrPorRstf)                 ? hal::ResetCause::kPowerOn
                 : (csr & kCsrBorRstf)                 ? hal::ResetCause::kBrownOut
                 : (csr & kCsrPinRstf)                 ? hal::ResetCause::kPin
                                                       : hal::ResetCause::kUnknown;
  reg(kRccCsr) = csr | kCsrRmvf;
  reg(kRccAhb1Enr) |= 0x7u;          // GPIOA, GPIOB, GPIOC
  reg(kRccApb1Enr) |= 1u | (1u << 3);  // TIM2, TIM5
  reg(kRccApb2Enr) |= 1u << 14;      // SYSCFG (EXTI port selection)
  (void)static_cast<uint32_t>(reg(kRccApb2Enr));  // read back: the clock is on before the first access
  // The cycle counter times STEP pulses and start-up delays.
  reg(kDemcr) |= 1u << 24;
  reg(kDwtCyccnt) = 0;
  reg(kDwtCtrl) |= 1u;

  for (int i = 0; i < static_cast<int>(hal::Pin::kCount); ++i) configure_pin(pin_map(static_cast<hal::Pin>(i)));
  // Drivers enabled (active low), LED off (lit when low).
  configure_pin({kDriverEnablePort, kDriverEnablePin, true, true, 0});
  reg(kDriverEnablePort + kBsrr) = 1u << (kDriverEnablePin + 16);
  configure_pin({kLedPort, kLedPin, true, true, 0});

  // TIM5: the microsecond clock, free-running 32 bits, an interrupt on each wrap.
  reg(kTim5 + kTimPsc) = kTimerClockHz / 1000000 - 1;
  reg(kTim5 + kTimArr) = 0xFFFFFFFF;
  reg(kTim5 + kTimEgr) = 1u;  // load the prescaler
  reg(kTim5 + kTimSr) = 0;
  reg(kTim5 + kTimDier) = kTimUif;
  reg(kTim5 + kTimCr1) = 1u;
  irq_enable(kIrqTim5, 3);

  // TIM2: the step timer, free-running at 96 MHz; compare channel 1 schedules steps.
  reg(kTim2 + kTimPsc) = 0;
  reg(kTim2 + kTimArr) = 0xFFFFFFFF;
  reg(kTim2 + kTimEgr) = 1u;
  reg(kTim2 + kTimSr) = 0;
  reg(kTim2 + kTimCr1) = 1u;
  irq_enable(kIrqTim2, 0);  // highest: a late step is a wrong position
}

void Stm32Board::write_pin(hal::Pin pin, bool level) {
  if (pin >= hal::Pin::kCount) return;
  const PinMap& p = pin_map(pin);
  if (!p.output) return;
  const int step = pin == hal::Pin::kStepX ? 0 : pin == hal::Pin::kStepY ? 1 : -1;
  if (step >= 0) {
    if (level) {
      step_high_cycles_[step] = reg(kDwtCyccnt);
    } else {
      while (reg(kDwtCyccnt) - step_high_cycles_[step] < kStepPulseCycles) {
      }
    }
  }
  const bool high = level != p.active_low;
  reg(p.port + kBsrr) = 1u << (p.number + (high ? 0 : 16));
}

bool Stm32Board::read_pin(hal::Pin pin) {
  if (pin >= hal::Pin::kCount) return false;
  const PinMap& p = pin_map(pin);
  const bool high = (reg(p.port + kIdr) >> p.number) & 1u;
  return high != p.active_low;
}

void Stm32Board::enable_drivers(bool on) {
  // EN is active low: reset the pin to enable, set it to disable (BSRR: one write, no read-modify).
  reg(kDriverEnablePort + kBsrr) = on ? 1u << (kDriverEnablePin + 16) : 1u << kDriverEnablePin;
}

void Stm32Board::on_rising_edge(hal::Pin pin, hal::EdgeHandler handler, void* context) {
  const PinMap& p = pin_map(pin);
  const uint32_t line = p.number;
  {
    CriticalSection masked;
    edges_[line] = {handler, context};
  }
  const uint32_t port_index = (p.port - kGpioA) / 0x400;
  const uint32_t cr = kSyscfgExticr1 + 4 * (line / 4);
  reg(cr) = (reg(cr) & ~(0xFu << (4 * (line % 4)))) | (port_index << (4 * (line % 4)));
  // A logical rising edge is an electrical falling one on an active-low input.
  if (p.active_low) {
    reg(kExtiFtsr) |= 1u << line;
    reg(kExtiRtsr) &= ~(1u << line);
  } else {
    reg(kExtiRtsr) |= 1u << line;
    reg(kExtiFtsr) &= ~(1u << line);
  }
  reg(kExtiPr) = 1u << line;
  reg(kExtiImr) |= 1u << line;
  irq_enable(exti_irq(line), 1);
}

void Stm32Board::edge_irq(uint32_t first_line, uint32_t last_line) {
  const uint32_t pending = reg(kExtiPr);
  for (uint32_t line = first_line; line <= last_line; ++line) {
    if ((pending & (1u << line)) == 0) continue;
    reg(kExtiPr) = 1u << line;  // write 1 to clear
    if (edges_[line].handler != nullptr) edges_[line].handler(edges_[line].context);
  }
}

uint32_t Stm32Board::ticks_for(uint32_t delay_ns) {
  // 96 MHz: 12/125 of a tick per nanosecond.
  const uint64_t scaled = uint64_t{delay_ns} * 12 + tick_remainder_;
  tick_remainder_ = static_cast<uint32_t>(scaled % 125);
  const uint64_t ticks = scaled / 125;
  return ticks == 0 ? 1 : static_cast<uint32_t>(ticks);
}

void Stm32Board::start_step_timer(uint32_t delay_ns, hal::TimerHandler handler, void* context) {
  CriticalSection masked;
  step_handler_ = handler;
  step_context_ = context;
  tick_remainder_ = 0;
  reg(kTim2 + kTimCcr1) = reg(kTim2 + kTimCnt) + ticks_for(delay_ns);
  reg(kTim2 + kTimSr) = ~kTimCc1if;
  reg(kTim2 + kTimDier) = kTimCc1if;
}

void Stm32Board::stop_step_timer() {
  reg(kTim2 + kTimDier) = 0;
  reg(kTim2 + kTimSr) = ~kTimCc1if;
}

void Stm32Board::step_timer_irq() {
  const uint32_t entered = reg(kTim2 + kTimCnt);
  reg(kTim2 + kTimSr) = ~kTimCc1if;
  if (step_handler_ == nullptr || reg(kTim2 + kTimDier) == 0) return;
  const uint32_t next_ns = step_handler_(step_context_);
  if (next_ns == 0) {
    stop_step_timer();
    return;
  }
  // Chained from the compare while on time; from this tick when it ran late (masked by a critical
  // section, say), so that the next step keeps its interval from this one instead of bursting.
  const uint32_t compare = hal::next_step_due<uint32_t>(reg(kTim2 + kTimCcr1), entered, ticks_for(next_ns), kLateStepTicks);
  reg(kTim2 + kTimCcr1) = compare;
  // Already due (the handler ran long, or the step is shorter than the handler): fire again now
  // rather than after the counter wraps in 44 s.
  if (static_cast<int32_t>(reg(kTim2 + kTimCnt) - compare) >= 0) reg(kTim2 + kTimEgr) = 1u << 1;  // CC1G
}

void Stm32Board::clock_irq() {
  if (reg(kTim5 + kTimSr) & kTimUif) {
    // Clearing the flag and counting the wrap must look like one step to now_us(): a gauge or
    // step interrupt between them would see neither the flag nor the count and read a time
    // 2^32 us (71.6 minutes) in the past.
    CriticalSection masked;
    reg(kTim5 + kTimSr) = ~kTimUif;
    clock_high_ = clock_high_ + 1;
  }
  if (reg(kTim5 + kTimSr) & kTimCc1if) {  // a wait() deadline: waking is all it is for
    reg(kTim5 + kTimSr) = ~kTimCc1if;
    reg(kTim5 + kTimDier) = kTimUif;
  }
}

uint64_t Stm32Board::now_us() {
  // Read the wrap count on both sides of the counter and take the pair that agrees; a wrap
  // pending but not yet counted (interrupts masked) shows as the overflow flag.
  for (;;) {
    const uint32_t high = clock_high_;
    uint32_t low = reg(kTim5 + kTimCnt);
    uint32_t wraps = high;
    if ((reg(kTim5 + kTimSr) & kTimUif) != 0) {
      low = reg(kTim5 + kTimCnt);
      wraps = high + 1;
    }
    if (clock_high_ == high) return (uint64_t{wraps} << 32) | low;
  }
}

size_t Stm32Board::link_write(const uint8_t* data, size_t size) { return usb_.write(data, size); }

size_t Stm32Board::link_read(uint8_t* data, size_t capacity) { return usb_.read(data, capacity); }

void Stm32Board::watchdog_start(uint32_t timeout_ms) {
  reg(kDbgmcuApb1Fz) |= 1u << 12;
  // The LSI runs at 32 kHz nominal (17 to 47 kHz, RM0383 and the datasheet): /64 gives 2 ms ticks,
  // so the timeout is between 0.7 and 1.9 times the one asked for; the firmware kicks at a quarter.
  uint32_t reload = timeout_ms / 2;
  if (reload < 1) reload = 1;
  if (reload > 0xFFF) reload = 0xFFF;
  reg(kIwdgKr) = 0xCCCC;  // start (it cannot be stopped again)
  reg(kIwdgKr) = 0x5555;  // unlock PR and RLR
  reg(kIwdgPr) = 4;       // /64
  reg(kIwdgRlr) = reload;
  // PR and RLR reach the LSI domain a few LSI cycles later; bounded, since the LSI may be slow.
  for (uint32_t spins = 0; (reg(kIwdgSr) & 0x3u) != 0 && spins < 100000; ++spins) {
  }
  reg(kIwdgKr) = 0xAAAA;
}

void Stm32Board::watchdog_kick() { reg(kIwdgKr) = 0xAAAA; }

void Stm32Board::spin_ns(uint32_t ns) {
  const uint32_t cycles = static_cast<uint32_t>(static_cast<uint64_t>(ns) * (kSysclkHz / 1000000) / 1000);
  const uint32_t start = reg(kDwtCyccnt);
  while (reg(kDwtCyccnt) - start < cycles) {
  }
}

bool Stm32Board::wait(uint64_t deadline_us) {
  const uint64_t now = now_us();
  if (deadline_us <= now || usb_.readable()) return true;
  if (deadline_us - now < 0x80000000u) {
    reg(kTim5 + kTimCcr1) = static_cast<uint32_t>(deadline_us);
    reg(kTim5 + kTimSr) = ~kTimCc1if;
    reg(kTim5 + kTimDier) = kTimUif | kTimCc1if;
  }
  // WFI wakes on a pending interrupt even with PRIMASK set, so a byte or an edge that arrives
  // between the check and the sleep is not slept through.
  mask_interrupts();
  if (!usb_.readable() && now_us() < deadline_us) wait_for_interrupt();
  unmask_interrupts();
  return true;
}

}  // namespace dg::stm32

// The register-level fake of the STM32F411's peripherals: register semantics from RM0383 (GPIO
// 8.4, EXTI 10.3, TIM2-5 13.4, IWDG 17.4, RCC_CSR 6.3.21) and the ARMv7-M NVIC.
#include "tests/support/fake_stm32.h"

#include <stdexcept>

#include "hw/boards/stm32f411/registers.h"

namespace dg::test {

namespace {

using namespace dg::stm32;

FakeStm32* installed = nullptr;

constexpr uint32_t kPortBases[3] = {kGpioA, kGpioB, kGpioC};
constexpr uint32_t kGpioOdr = 0x14;
constexpr uint32_t kSyscfgExticr4 = kSyscfgExticr1 + 12;
constexpr uint32_t kNvicIserEnd = kNvicIser + 12;
constexpr uint32_t kTimerSpan = 0x400;
constexpr uint64_t kNever = UINT64_MAX;
// Handlers run back to back this many times without the source clearing: an interrupt storm.
constexpr int kStormDeliveries = 1000000;

FakeStm32& bus() {
  if (installed == nullptr) throw std::logic_error("no FakeStm32 installed for the board's register accesses");
  return *installed;
}

// The first tick after `from` (unwrapped) whose low 32 bits equal `value`.
uint64_t next_tick_at(uint64_t from, uint32_t value) {
  const uint32_t ahead = value - static_cast<uint32_t>(from + 1);
  return from + 1 + ahead;
}

}  // namespace

FakeStm32::FakeStm32() {
  if (installed != nullptr) throw std::logic_error("one FakeStm32 at a time");
  installed = this;
}

FakeStm32::~FakeStm32() { installed = nullptr; }

void FakeStm32::set_handler(int irq, std::function<void()> handler) { handlers_[irq] = std::move(handler); }

void FakeStm32::run_for(uint64_t cycles) { advance_to(now_ + cycles, true); }

void FakeStm32::at(uint64_t cycle, std::function<void()> event) {
  if (cycle <= now_) {
    event();
    deliver();
    return;
  }
  events_.emplace(cycle, std::move(event));
}

FakeStm32::Port* FakeStm32::port_at(uint32_t address, uint32_t& offset) {
  for (int p = 0; p < 3; ++p) {
    if (address >= kPortBases[p] && address < kPortBases[p] + 0x400) {
      offset = address - kPortBases[p];
      return &ports_[p];
    }
  }
  return nullptr;
}

FakeStm32::Timer* FakeStm32::timer_at(uint32_t address, uint32_t& offset) {
  if (address >= kTim2 && address < kTim2 + kTimerSpan) {
    offset = address - kTim2;
    return &tim2_;
  }
  if (address >= kTim5 && address < kTim5 + kTimerSpan) {
    offset = address - kTim5;
    return &tim5_;
  }
  return nullptr;
}

uint32_t FakeStm32::input_levels(const Port& p) const {
  uint32_t levels = 0;
  for (int pin = 0; pin < 16; ++pin) {
    const uint32_t bit = 1u << pin;
    const uint32_t mode = (p.moder >> (2 * pin)) & 3u;
    bool high;
    if (mode == 1) {
      high = p.odr & bit;
    } else if (p.driven & bit) {
      high = p.level & bit;
    } else {
      high = ((p.pupdr >> (2 * pin)) & 3u) == 1;
    }
    if (high) levels |= bit;
  }
  return levels;
}

void FakeStm32::set_odr(uint32_t port_base, Port& p, uint32_t odr) {
  const uint32_t before_inputs = input_levels(p);
  const uint32_t changed = (p.odr ^ odr) & 0xFFFFu;
  p.odr = odr & 0xFFFFu;
  for (int pin = 0; pin < 16; ++pin) {
    if (!(changed & (1u << pin))) continue;
    const PinChange change{port_base, pin, (p.odr >> pin) & 1u ? true : false, now_};
    if (on_output) on_output(change);
  }
  input_changed(port_base, before_inputs, input_levels(p));
}

void FakeStm32::input_changed(uint32_t port_base, uint32_t before, uint32_t after) {
  const uint32_t port_index = (port_base - kGpioA) / 0x400;
  for (uint32_t line = 0; line < 16; ++line) {
    const uint32_t bit = 1u << line;
    if (((before ^ after) & bit) == 0) continue;
    if (((exticr_[line / 4] >> (4 * (line % 4))) & 0xFu) != port_index) continue;
    const bool rising = after & bit;
    if ((rising && (exti_rtsr_ & bit)) || (!rising && (exti_ftsr_ & bit))) exti_pr_ |= bit;
  }
}

void FakeStm32::drive(uint32_t port, int pin, bool high) {
  uint32_t offset = 0;
  Port* p = port_at(port, offset);
  if (p == nullptr) throw std::invalid_argument("no such GPIO port");
  const uint32_t before = input_levels(*p);
  p->driven |= 1u << pin;
  p->level = high ? p->level | (1u << pin) : p->level & ~(1u << pin);
  input_changed(port, before, input_levels(*p));
  deliver();
}

void FakeStm32::release(uint32_t port, int pin) {
  uint32_t offset = 0;
  Port* p = port_at(port, offset);
  if (p == nullptr) throw std::invalid_argument("no such GPIO port");
  const uint32_t before = input_levels(*p);
  p->driven &= ~(1u << pin);
  input_changed(port, before, input_levels(*p));
  deliver();
}

bool FakeStm32::output_high(uint32_t port, int pin) const {
  for (int p = 0; p < 3; ++p) {
    if (kPortBases[p] == port) return (ports_[p].odr >> pin) & 1u;
  }
  return false;
}

uint32_t FakeStm32::mode(uint32_t port, int pin) const {
  for (int p = 0; p < 3; ++p) {
    if (kPortBases[p] == port) return (ports_[p].moder >> (2 * pin)) & 3u;
  }
  return 0;
}

uint32_t FakeStm32::pull(uint32_t port, int pin) const {
  for (int p = 0; p < 3; ++p) {
    if (kPortBases[p] == port) return (ports_[p].pupdr >> (2 * pin)) & 3u;
  }
  return 0;
}

void FakeStm32::set_counter(uint32_t timer, uint32_t value) {
  Timer& t = timer == kTim2 ? tim2_ : tim5_;
  t.base_cycle = now_;
  t.base_ticks = value;
}

uint32_t FakeStm32::read(uint32_t address) {
  access();
  const uint32_t value = value_at(address);
  deliver();
  return value;
}

uint32_t FakeStm32::value_at(uint32_t address) {
  uint32_t offset = 0;
  if (Port* p = port_at(address, offset)) {
    switch (offset) {
      case kModer: return p->moder;
      case kOspeedr: return p->ospeedr;
      case kPupdr: return p->pupdr;
      case kIdr: return input_levels(*p);
      case kGpioOdr: return p->odr;
      case kBsrr: return 0;  // write-only
      default: return plain_[address];
    }
  }
  if (Timer* t = timer_at(address, offset)) {
    switch (offset) {
      case kTimCr1: return t->cr1;
      case kTimDier: return t->dier;
      case kTimSr: return t->sr;
      case kTimCnt: return static_cast<uint32_t>(t->ticks(now_));
      case kTimPsc: return t->psc;
      case kTimArr: return 0xFFFFFFFFu;
      case kTimCcr1: return t->ccr1;
      default: return 0;
    }
  }
  switch (address) {
    case kExtiImr: return exti_imr_;
    case kExtiRtsr: return exti_rtsr_;
    case kExtiFtsr: return exti_ftsr_;
    case kExtiPr: return exti_pr_;
    case kDwtCtrl: return dwt_ctrl_;
    case kDwtCyccnt: return (dwt_ctrl_ & 1u) ? static_cast<uint32_t>(now_ - dwt_base_) : 0;
    case kRccCsr: return csr_;
    case kIwdgSr: return 0;  // PR and RLR reach the LSI domain at once here
    default: break;
  }
  if (address >= kSyscfgExticr1 && address <= kSyscfgExticr4) return exticr_[(address - kSyscfgExticr1) / 4];
  if (address >= kNvicIser && address < kNvicIserEnd) return nvic_enabled_[(address - kNvicIser) / 4];
  if (address >= kUniqueId && address < kUniqueId + 12) return 0x20240000u + (address - kUniqueId);
  return plain_[address];
}

void FakeStm32::write(uint32_t address, uint32_t value) {
  access();
  uint32_t offset = 0;
  if (Port* p = port_at(address, offset)) {
    const uint32_t base = address - offset;
    switch (offset) {
      case kModer: {
        const uint32_t before = input_levels(*p);
        p->moder = value;
        input_changed(base, before, input_levels(*p));
        break;
      }
      case kOspeedr: p->ospeedr = value; break;
      case kPupdr: {
        const uint32_t before = input_levels(*p);
        p->pupdr = value;
        input_changed(base, before, input_levels(*p));
        break;
      }
      case kGpioOdr: set_odr(base, *p, value); break;
      case kBsrr: set_odr(base, *p, (p->odr & ~(value >> 16)) | (value & 0xFFFFu)); break;  // set wins
      default: plain_[address] = value; break;
    }
    deliver();
    return;
  }
  if (Timer* t = timer_at(address, offset)) {
    switch (offset) {
      case kTimCr1:
        if ((value & 1u) != (t->cr1 & 1u)) {  // the count freezes or resumes here
          t->base_ticks = t->ticks(now_);
          t->base_cycle = now_;
        }
        t->cr1 = value;
        break;
      case kTimDier: t->dier = value; break;
      case kTimSr: t->sr &= value; break;  // rc_w0: writing 0 clears, 1 leaves
      case kTimEgr:
        if (value & 1u) {  // UG: the counter restarts and the prescaler loads
          t->base_ticks = 0;
          t->base_cycle = now_;
          t->active_psc = t->psc;
          t->sr |= kTimUif;
        }
        if (value & 2u) t->sr |= kTimCc1if;  // CC1G
        break;
      case kTimCnt: t->base_ticks = value, t->base_cycle = now_; break;
      case kTimPsc: t->psc = value & 0xFFFFu; break;
      case kTimCcr1: t->ccr1 = value; break;
      default: break;
    }
    deliver();
    return;
  }
  switch (address) {
    case kExtiImr: exti_imr_ = value; break;
    case kExtiRtsr: exti_rtsr_ = value; break;
    case kExtiFtsr: exti_ftsr_ = value; break;
    case kExtiPr: exti_pr_ &= ~value; break;  // rc_w1
    case kDwtCtrl: dwt_ctrl_ = value; break;
    case kDwtCyccnt: dwt_base_ = now_ - value; break;
    case kRccCsr:
      if (value & kCsrRmvf) csr_ &= 0x00FFFFFFu;
      break;
    case kIwdgKr:
      if (value == 0xCCCC) {
        iwdg_running_ = true;
        iwdg_kicked_ = now_;
      } else if (value == 0x5555) {
        iwdg_unlocked_ = true;
      } else if (value == 0xAAAA) {
        iwdg_kicked_ = now_;
        iwdg_unlocked_ = false;
      }
      break;
    case kIwdgPr:
      if (iwdg_unlocked_) iwdg_pr_ = value & 7u;
      break;
    case kIwdgRlr:
      if (iwdg_unlocked_) iwdg_rlr_ = value & 0xFFFu;
      break;
    case kScbAircr:
      if ((value >> 16) == 0x05FAu && (value & (1u << 2))) reset_requested_ = true;
      break;
    default:
      if (address >= kSyscfgExticr1 && address <= kSyscfgExticr4) {
        exticr_[(address - kSyscfgExticr1) / 4] = value;
      } else if (address >= kNvicIser && address < kNvicIserEnd) {
        nvic_enabled_[(address - kNvicIser) / 4] |= value;  // write 1 to enable
      } else {
        plain_[address] = value;
      }
  }
  deliver();
}

void FakeStm32::write_byte(uint32_t address, uint8_t value) {
  access();
  if (address >= kNvicIpr && address < kNvicIpr + sizeof nvic_priority_) {
    nvic_priority_[address - kNvicIpr] = value;
  } else {
    plain_[address] = value;
  }
  deliver();
}

void FakeStm32::set_primask(uint32_t value) {
  primask_ = value & 1u;
  deliver();
}

void FakeStm32::wait_for_interrupt() {
  // Wakes on a pending enabled interrupt, masked or not (ARMv7-M B1.5.19); with nothing ahead
  // that could raise one, returns as a spurious wake would.
  for (;;) {
    for (int irq = 0; irq < 96; ++irq) {
      if (pending(irq)) return;
    }
    const uint64_t next = next_event();
    if (next == kNever) return;
    advance_to(next, true);
  }
}

uint64_t FakeStm32::next_event() const {
  uint64_t next = kNever;
  if (!events_.empty()) next = std::min(next, events_.begin()->first);
  for (const Timer* t : {&tim2_, &tim5_}) {
    if (!(t->cr1 & 1u)) continue;
    const uint64_t now_ticks = t->ticks(now_);
    const uint64_t per_tick = t->active_psc + 1;
    // The cycle at which the count reaches `tick`.
    auto cycle_of = [&](uint64_t tick) { return t->base_cycle + (tick - t->base_ticks) * per_tick; };
    next = std::min(next, cycle_of(next_tick_at(now_ticks, t->ccr1)));
    next = std::min(next, cycle_of(next_tick_at(now_ticks, 0)));
  }
  if (iwdg_running_ && !watchdog_fired_) {
    const uint64_t period = uint64_t{iwdg_rlr_ + 1} * (4u << iwdg_pr_) * (kCoreHz / 32000);
    next = std::min(next, iwdg_kicked_ + period + 1);
  }
  return next;
}

void FakeStm32::step_to(uint64_t cycle) {
  for (Timer* t : {&tim2_, &tim5_}) {
    if (!(t->cr1 & 1u)) continue;
    const uint64_t from = t->ticks(now_), to = t->ticks(cycle);
    if (to == from) continue;
    if (next_tick_at(from, t->ccr1) <= to) t->sr |= kTimCc1if;
    if (next_tick_at(from, 0) <= to) t->sr |= kTimUif;
  }
  now_ = cycle;
  if (iwdg_running_ && !watchdog_fired_) {
    const uint64_t period = uint64_t{iwdg_rlr_ + 1} * (4u << iwdg_pr_) * (kCoreHz / 32000);
    if (now_ - iwdg_kicked_ > period) watchdog_fired_ = true;
  }
}

void FakeStm32::advance_to(uint64_t cycle, bool deliver_between) {
  while (now_ < cycle) {
    step_to(std::min(cycle, std::max(next_event(), now_ + 1)));
    while (!events_.empty() && events_.begin()->first <= now_) {
      auto event = std::move(events_.begin()->second);
      events_.erase(events_.begin());
      event();
    }
    if (deliver_between) deliver();
  }
}

// An interrupt that falls due during the access is taken after it, at the next instruction
// boundary: the caller delivers once the read has its value or the write its effect.
void FakeStm32::access() {
  const bool outer = in_delivery_step_;
  in_delivery_step_ = true;
  advance_to(now_ + kAccessCycles, false);
  in_delivery_step_ = outer;
}

bool FakeStm32::pending(int irq) const {
  if (!((nvic_enabled_[irq / 32] >> (irq % 32)) & 1u)) return false;
  const uint32_t exti = exti_pr_ & exti_imr_;
  switch (irq) {
    case kIrqTim2: return tim2_.sr & tim2_.dier & (kTimUif | kTimCc1if);
    case kIrqTim5: return tim5_.sr & tim5_.dier & (kTimUif | kTimCc1if);
    case kIrqExti0: case kIrqExti1: case kIrqExti2: case kIrqExti3: case kIrqExti4:
      return exti & (1u << (irq - kIrqExti0));
    case kIrqExti9_5: return exti & 0x03E0u;
    case kIrqExti15_10: return exti & 0xFC00u;
    default: return false;
  }
}

void FakeStm32::deliver() {
  if (primask_ || in_delivery_step_) return;
  for (int taken = 0;; ++taken) {
    if (taken == kStormDeliveries) throw std::runtime_error("interrupt storm: a handler does not clear its source");
    const int running = active_priorities_.empty() ? 256 : active_priorities_.back();
    int best = -1, best_priority = running;
    for (int irq = 0; irq < 96; ++irq) {
      if (!pending(irq)) continue;
      const int priority = nvic_priority_[irq] >> 4;
      if (priority < best_priority) best = irq, best_priority = priority;
    }
    if (best < 0) return;
    auto handler = handlers_.find(best);
    if (handler == handlers_.end()) throw std::runtime_error("interrupt " + std::to_string(best) + " has no handler");
    in_delivery_step_ = true;
    advance_to(now_ + kEntryCycles, false);
    in_delivery_step_ = false;
    active_priorities_.push_back(best_priority);
    deepest_nesting_ = std::max(deepest_nesting_, static_cast<int>(active_priorities_.size()));
    handler->second();
    active_priorities_.pop_back();
    if (primask_) return;
  }
}

}  // namespace dg::test

namespace dg::stm32 {

uint32_t bus_read(uint32_t address) { return dg::test::bus().read(address); }
void bus_write(uint32_t address, uint32_t value) { dg::test::bus().write(address, value); }
void bus_write_byte(uint32_t address, uint8_t value) { dg::test::bus().write_byte(address, value); }
uint32_t interrupts_masked() { return dg::test::bus().primask(); }
void mask_interrupts() { dg::test::bus().set_primask(1); }
void unmask_interrupts() { dg::test::bus().set_primask(0); }
void restore_interrupts(uint32_t primask) { dg::test::bus().set_primask(primask); }
void wait_for_interrupt() { dg::test::bus().wait_for_interrupt(); }

}  // namespace dg::stm32

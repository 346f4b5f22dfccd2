// The STM32F411 registers this board touches, by address (RM0383 memory map and register
// chapters; Cortex-M4 system registers from the ARMv7-M architecture manual). No vendor headers.
#pragma once
#include <cstdint>

#if !defined(__arm__)
// On the host the board's code runs against a register-level fake of these peripherals
// (tests/support/fake_stm32.h): reg() and every PRIMASK change go through it.
#include "hw/boards/stm32f411/register_bus.h"
#endif

namespace dg::stm32 {

#if defined(__arm__)
inline volatile uint32_t& reg(uint32_t address) { return *reinterpret_cast<volatile uint32_t*>(address); }
#endif

// Reset and clock control (RM0383 6.3).
constexpr uint32_t kRcc = 0x40023800;
constexpr uint32_t kRccCr = kRcc + 0x00, kRccPllCfgr = kRcc + 0x04, kRccCfgr = kRcc + 0x08;
constexpr uint32_t kRccAhb1Enr = kRcc + 0x30, kRccAhb2Enr = kRcc + 0x34;
constexpr uint32_t kRccApb1Enr = kRcc + 0x40, kRccApb2Enr = kRcc + 0x44;
constexpr uint32_t kPwrCr = 0x40007000;
// RCC_CSR's reset flags (RM0383 6.3.21) and the independent watchdog (RM0383 17.4).
constexpr uint32_t kRccCsr = kRcc + 0x74;
constexpr uint32_t kCsrRmvf = 1u << 24, kCsrBorRstf = 1u << 25, kCsrPinRstf = 1u << 26, kCsrPorRstf = 1u << 27,
                   kCsrSftRstf = 1u << 28, kCsrIwdgRstf = 1u << 29, kCsrWwdgRstf = 1u << 30;
constexpr uint32_t kIwdg = 0x40003000;
constexpr uint32_t kIwdgKr = kIwdg + 0x00, kIwdgPr = kIwdg + 0x04, kIwdgRlr = kIwdg + 0x08, kIwdgSr = kIwdg + 0x0C;
constexpr uint32_t kDbgmcuApb1Fz = 0xE0042008;  // bit 12: the watchdog stops while a debugger halts the core
constexpr uint32_t kFlashAcr = 0x40023C00;

// GPIO ports A-C (RM0383 8.4): the registers used here (MODER, OSPEEDR, PUPDR, IDR, BSRR, AFRH).
constexpr uint32_t kGpioA = 0x40020000, kGpioB = 0x40020400, kGpioC = 0x40020800;
constexpr uint32_t kModer = 0x00, kOspeedr = 0x08, kPupdr = 0x0C, kIdr = 0x10, kBsrr = 0x18, kAfrh = 0x24;

// External interrupts (RM0383 7.2, 10.3).
constexpr uint32_t kSyscfgExticr1 = 0x40013800 + 0x08;
constexpr uint32_t kExti = 0x40013C00;
constexpr uint32_t kExtiImr = kExti + 0x00, kExtiRtsr = kExti + 0x08, kExtiFtsr = kExti + 0x0C,
                   kExtiPr = kExti + 0x14;

// General-purpose 32-bit timers TIM2 and TIM5 on APB1 (RM0383 13.4).
constexpr uint32_t kTim2 = 0x40000000, kTim5 = 0x40000C00;
constexpr uint32_t kTimCr1 = 0x00, kTimDier = 0x0C, kTimSr = 0x10, kTimEgr = 0x14, kTimCnt = 0x24, kTimPsc = 0x28,
                   kTimArr = 0x2C, kTimCcr1 = 0x34;
constexpr uint32_t kTimUif = 1u << 0, kTimCc1if = 1u << 1;

// The 96-bit unique device ID (RM0383 24.2).
constexpr uint32_t kUniqueId = 0x1FFF7A10;

// Cortex-M4 system control space.
constexpr uint32_t kNvicIser = 0xE000E100, kNvicIpr = 0xE000E400;
constexpr uint32_t kScbAircr = 0xE000ED0C;
constexpr uint32_t kDemcr = 0xE000EDFC, kDwtCtrl = 0xE0001000, kDwtCyccnt = 0xE0001004;

// Interrupt numbers (RM0383 table 37).
enum Irq : uint8_t {
  kIrqExti0 = 6, kIrqExti1 = 7, kIrqExti2 = 8, kIrqExti3 = 9, kIrqExti4 = 10,
  kIrqExti9_5 = 23, kIrqTim2 = 28, kIrqExti15_10 = 40, kIrqTim5 = 50, kIrqOtgFs = 67,
};
constexpr int kIrqCount = 86;

#if defined(__arm__)
inline void irq_enable(Irq irq, uint8_t priority) {
  reinterpret_cast<volatile uint8_t*>(kNvicIpr)[irq] = static_cast<uint8_t>(priority << 4);  // 4 priority bits
  reg(kNvicIser + 4 * (irq / 32)) = 1u << (irq % 32);
}

inline uint32_t interrupts_masked() {
  uint32_t primask;
  asm volatile("mrs %0, primask" : "=r"(primask));
  return primask;
}
inline void mask_interrupts() { asm volatile("cpsid i" ::: "memory"); }
inline void unmask_interrupts() { asm volatile("cpsie i" ::: "memory"); }
inline void restore_interrupts(uint32_t primask) { asm volatile("msr primask, %0" ::"r"(primask) : "memory"); }
// Sleeps until an interrupt is pending (it wakes even with PRIMASK set).
inline void wait_for_interrupt() { asm volatile("wfi"); }
#else
inline void irq_enable(Irq irq, uint8_t priority) {
  bus_write_byte(kNvicIpr + irq, static_cast<uint8_t>(priority << 4));
  reg(kNvicIser + 4 * (irq / 32)) = 1u << (irq % 32);
}
#endif

// Interrupts off around a few lines that share state with a handler.
class CriticalSection {
 public:
  CriticalSection() : primask_(interrupts_masked()) { mask_interrupts(); }
  ~CriticalSection() { restore_interrupts(primask_); }
  CriticalSection(const CriticalSection&) = delete;
  CriticalSection& operator=(const CriticalSection&) = delete;

 private:
  uint32_t primask_;
};

constexpr uint32_t kSysclkHz = 96000000;
constexpr uint32_t kTimerClockHz = 96000000;  // APB1 at 48 MHz with a divider: its timers run at twice that

}  // namespace dg::stm32

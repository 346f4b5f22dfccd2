// Instruction counting on QEMU's Cortex-M4 under -icount: SysTick ticks, calibrated against a loop
// of known length, so the figures do not depend on the emulated clock.
#pragma once
#include <cstdint>

namespace dg::bench {

// What the instructions were built for: a Cortex-M0+ build (ARMv6-M: no 64-bit multiply, no
// divide instruction) runs on QEMU's Cortex-M4 too, and its count is the M0+'s.
#if defined(__ARM_ARCH_6M__)
inline constexpr const char* kCoreName = "Cortex-M0+ build (ARMv6-M) on QEMU mps2-an386, -icount";
#else
inline constexpr const char* kCoreName = "Cortex-M4 (QEMU mps2-an386, -icount)";
#endif

inline volatile uint32_t* const kSysTick = reinterpret_cast<volatile uint32_t*>(0xE000E010);

inline void start_ticks() {
  kSysTick[0] = 0;
  kSysTick[1] = 0xFFFFFF;
  kSysTick[2] = 0;
  kSysTick[0] = 5;  // enable, processor clock, no interrupt
}

inline uint32_t ticks_since_start() { return 0xFFFFFF - (kSysTick[2] & 0xFFFFFF); }

// 2 instructions per round (subs, bne) plus a few around.
__attribute__((noinline)) inline void known_loop(uint32_t rounds) {
  asm volatile(
      ".syntax unified\n"  // ARMv6-M's assembler reads inline code in the older syntax otherwise
      "1: subs %0, %0, #1\n"
      "   bne 1b\n"
      : "+r"(rounds)
      :
      : "cc");
}

// Instructions per SysTick tick, in thousandths.
inline uint64_t milli_instructions_per_tick() {
  constexpr uint32_t kRounds = 1000000;
  start_ticks();
  known_loop(kRounds);
  const uint32_t ticks = ticks_since_start();
  return (2ull * kRounds * 1000 + ticks / 2) / ticks;
}

}  // namespace dg::bench

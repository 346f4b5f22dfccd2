// The C and C++ run-time start every Cortex-M image shares: the stack painted (for its high-water
// mark), .data copied from flash, .bss zeroed, the FPU enabled where the build uses one, then
// (after whatever the board must do first) the constructors.
// The symbols come from each image's linker script.
#pragma once
#include <cstdint>

extern "C" {
extern uint32_t __data_load, __data_start, __data_end, __bss_start, __bss_end, __stack_bottom, __stack_top;
extern void (*__init_array_start[])(), (*__init_array_end[])();
}

namespace dg::cortex_m {

inline void init_memory_and_fpu() {
  const uint32_t* from = &__data_load;
  for (uint32_t* to = &__data_start; to < &__data_end;) *to++ = *from++;
  for (uint32_t* to = &__bss_start; to < &__bss_end;) *to++ = 0;
#ifdef __ARM_FP
  // CPACR: full access to CP10 and CP11, as the hard-float ABI of the build expects. A build
  // without an FPU (a Cortex-M0+) has no CPACR to write.
  *reinterpret_cast<volatile uint32_t*>(0xE000ED88) |= 0xFu << 20;
#endif
}

// The stack is painted with this word at reset; the deepest word no longer holding it is the
// stack's high-water mark since then.
constexpr uint32_t kStackPaint = 0x57AC0DE5u;

// Paints the stack from its bottom up to just below the caller's frame. Called first at reset, on
// the stack it paints, so it keeps 64 bytes clear of its own stack pointer.
__attribute__((always_inline)) inline void paint_stack() {
  uint32_t sp = 0;
  asm volatile("mov %0, sp" : "=r"(sp));
  for (uint32_t* word = &__stack_bottom; reinterpret_cast<uint32_t>(word) + 64 < sp; ++word) *word = kStackPaint;
}

// The most stack used since reset, in bytes: from the top down to the deepest word that lost its
// paint. The whole stack means it may have overflowed.
inline uint32_t stack_used_bytes() {
  const uint32_t* word = &__stack_bottom;
  while (word < &__stack_top && *word == kStackPaint) ++word;
  return static_cast<uint32_t>(reinterpret_cast<uintptr_t>(&__stack_top) - reinterpret_cast<uintptr_t>(word));
}

inline uint32_t stack_size_bytes() {
  return static_cast<uint32_t>(reinterpret_cast<uintptr_t>(&__stack_top) - reinterpret_cast<uintptr_t>(&__stack_bottom));
}

inline void run_constructors() {
  for (auto* f = __init_array_start; f < __init_array_end; ++f) (*f)();
}

}  // namespace dg::cortex_m

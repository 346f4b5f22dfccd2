// The C and C++ run-time start every Cortex-M4F image shares: .data copied from flash, .bss
// zeroed, the FPU enabled, then (after whatever the board must do first) the constructors.
// The symbols come from each image's linker script.
#pragma once
#include <cstdint>

extern "C" {
extern uint32_t __data_load, __data_start, __data_end, __bss_start, __bss_end, __stack_top;
extern void (*__init_array_start[])(), (*__init_array_end[])();
}

namespace dg::cortex_m {

inline void init_memory_and_fpu() {
  const uint32_t* from = &__data_load;
  for (uint32_t* to = &__data_start; to < &__data_end;) *to++ = *from++;
  for (uint32_t* to = &__bss_start; to < &__bss_end;) *to++ = 0;
  // CPACR: full access to CP10 and CP11, as the hard-float ABI of the build expects.
  *reinterpret_cast<volatile uint32_t*>(0xE000ED88) |= 0xFu << 20;
}

inline void run_constructors() {
  for (auto* f = __init_array_start; f < __init_array_end; ++f) (*f)();
}

}  // namespace dg::cortex_m

// Minimal start-up for images on QEMU's mps2-an386: vectors, data/bss, constructors,
// the FPU on, then main; the result leaves through Arm semihosting.
#include <cstdint>

#include "hw/boards/qemu-mps2/semihosting.h"

extern "C" {
extern uint32_t __data_load, __data_start, __data_end, __bss_start, __bss_end, __stack_top;
extern void (*__init_array_start[])(), (*__init_array_end[])();
int main();

[[noreturn]] void reset_handler() {
  const uint32_t* from = &__data_load;
  for (uint32_t* to = &__data_start; to < &__data_end;) *to++ = *from++;
  for (uint32_t* to = &__bss_start; to < &__bss_end;) *to++ = 0;
  // CPACR: full access to CP10 and CP11, as the hard-float ABI of the build expects.
  *reinterpret_cast<volatile uint32_t*>(0xE000ED88) |= 0xFu << 20;
  for (auto* f = __init_array_start; f < __init_array_end; ++f) (*f)();
  dg::bench::semihost_exit(main());
}

[[noreturn]] void fault_handler() { dg::bench::semihost_exit(99); }

__attribute__((section(".vectors"), used)) const void* const vectors[16] = {
    &__stack_top, reinterpret_cast<const void*>(reset_handler), reinterpret_cast<const void*>(fault_handler),
    reinterpret_cast<const void*>(fault_handler), reinterpret_cast<const void*>(fault_handler),
    reinterpret_cast<const void*>(fault_handler), reinterpret_cast<const void*>(fault_handler)};
}

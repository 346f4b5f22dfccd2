// Minimal start-up for images on QEMU's mps2-an386: vectors, data/bss, constructors,
// the FPU on, then main; the result leaves through Arm semihosting.
#include <cstdint>

#include "hw/boards/cortex-m/runtime.h"
#include "hw/boards/qemu-mps2/semihosting.h"

extern "C" {
int main();

[[noreturn]] void reset_handler() {
  dg::cortex_m::paint_stack();
  dg::cortex_m::init_memory_and_fpu();
  dg::cortex_m::run_constructors();
  dg::bench::semihost_exit(main());
}

[[noreturn]] void fault_handler() { dg::bench::semihost_exit(99); }

__attribute__((section(".vectors"), used)) const void* const vectors[16] = {
    &__stack_top, reinterpret_cast<const void*>(reset_handler), reinterpret_cast<const void*>(fault_handler),
    reinterpret_cast<const void*>(fault_handler), reinterpret_cast<const void*>(fault_handler),
    reinterpret_cast<const void*>(fault_handler), reinterpret_cast<const void*>(fault_handler)};
}

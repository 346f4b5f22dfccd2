// What newlib asks of an image without an operating system: no heap, and no way out but a reset.
// Nothing in the firmware allocates, exits or raises signals; these are reached only if
// something goes badly wrong.
#include <cstddef>

#include "hw/boards/stm32f411/interrupts.h"

extern "C" {

[[noreturn]] void _exit(int) { dg::stm32::fatal_stop(); }

void* _sbrk(ptrdiff_t) { return reinterpret_cast<void*>(-1); }  // no heap

int _kill(int, int) { return -1; }

int _getpid() { return 1; }

}

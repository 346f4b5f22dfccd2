// What newlib asks of an image without an operating system: no heap, and an exit through Arm
// semihosting (QEMU ends with the status). Nothing in the firmware allocates or raises signals;
// these are reached only if something goes badly wrong.
#include <cstddef>
#include <cstdint>

#include "hw/boards/qemu-mps2/semihosting.h"

extern "C" {

[[noreturn]] void _exit(int status) { dg::bench::semihost_exit(status); }

void* _sbrk(ptrdiff_t) { return reinterpret_cast<void*>(-1); }  // no heap

int _kill(int, int) { return -1; }

int _getpid() { return 1; }

}

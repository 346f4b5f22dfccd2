// Arm semihosting for the benchmark image: text out and exit status, no C library needed.
#pragma once
#include <cstdint>

namespace dg::bench {

inline int semihost(int operation, const void* argument) {
  register int r0 asm("r0") = operation;
  register const void* r1 asm("r1") = argument;
  asm volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

inline void write_text(const char* text) { semihost(0x04, text); }  // SYS_WRITE0

inline void write_number(uint64_t value) {
  char digits[24];
  int n = 23;
  digits[n] = '\0';
  do {
    digits[--n] = static_cast<char>('0' + value % 10);
    value /= 10;
  } while (value != 0);
  write_text(digits + n);
}

[[noreturn]] inline void semihost_exit(int status) {
  // SYS_EXIT_EXTENDED (0x20) with ADP_Stopped_ApplicationExit carries the status to QEMU.
  const uint32_t block[2] = {0x20026, static_cast<uint32_t>(status)};
  semihost(0x20, block);
  for (;;) {
  }
}

}  // namespace dg::bench

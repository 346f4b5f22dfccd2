// The host build's register bus: every access the board's code makes to a peripheral register,
// and every change of PRIMASK, goes to a register-level fake of the chip (tests/support/fake_stm32.h).
#pragma once
#include <cstdint>

namespace dg::stm32 {

// Implemented by the fake, which models each peripheral's side effects (set/reset registers,
// write-1-to-clear flags, counters that run with time) and delivers interrupts between accesses.
uint32_t bus_read(uint32_t address);
void bus_write(uint32_t address, uint32_t value);
void bus_write_byte(uint32_t address, uint8_t value);
uint32_t interrupts_masked();
void mask_interrupts();
void unmask_interrupts();
void restore_interrupts(uint32_t primask);
void wait_for_interrupt();

// What reg() gives on the host: a register by address whose reads and writes are bus accesses,
// so `reg(a) |= bit` is a read and a write, as on the chip.
class RegisterRef {
 public:
  explicit RegisterRef(uint32_t address) : address_(address) {}
  RegisterRef(const RegisterRef&) = default;
  operator uint32_t() const { return bus_read(address_); }
  RegisterRef& operator=(uint32_t value) {
    bus_write(address_, value);
    return *this;
  }
  // `reg(a) = reg(b)` copies the value, not the address.
  RegisterRef& operator=(const RegisterRef& other) { return *this = static_cast<uint32_t>(other); }
  RegisterRef& operator|=(uint32_t bits) { return *this = bus_read(address_) | bits; }
  RegisterRef& operator&=(uint32_t bits) { return *this = bus_read(address_) & bits; }

 private:
  uint32_t address_;
};

inline RegisterRef reg(uint32_t address) { return RegisterRef(address); }

}  // namespace dg::stm32

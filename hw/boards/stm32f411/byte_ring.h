// A single-producer, single-consumer byte ring between an interrupt handler and the main loop:
// each index is written by one side only, so neither needs to mask the other.
#pragma once
#include <cstddef>
#include <cstdint>

namespace dg::stm32 {

template <size_t Capacity>
class ByteRing {
  static_assert((Capacity & (Capacity - 1)) == 0, "a power of two, so the indexes may wrap freely");

 public:
  size_t size() const { return static_cast<size_t>(head_ - tail_); }
  size_t free_space() const { return Capacity - size(); }

  // Producer side.
  size_t push(const uint8_t* data, size_t count) {
    size_t n = 0;
    for (; n < count && size() < Capacity; ++n) {
      bytes_[head_ % Capacity] = data[n];
      asm volatile("" ::: "memory");  // the byte is stored before the index that publishes it
      head_ = head_ + 1;
    }
    return n;
  }
  void push_byte(uint8_t byte) { push(&byte, 1); }

  // Consumer side.
  size_t pop(uint8_t* out, size_t capacity) {
    size_t n = 0;
    for (; n < capacity && size() > 0; ++n) {
      out[n] = bytes_[tail_ % Capacity];
      asm volatile("" ::: "memory");
      tail_ = tail_ + 1;
    }
    return n;
  }
  // Drops what the producer has published so far (consumer side).
  void drop() { tail_ = head_; }

 private:
  uint8_t bytes_[Capacity] = {};
  volatile uint32_t head_ = 0;
  volatile uint32_t tail_ = 0;
};

}  // namespace dg::stm32

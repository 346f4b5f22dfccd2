// Consistent Overhead Byte Stuffing: removes every zero byte so 0x00 can delimit frames.
#pragma once
#include <cstddef>
#include <cstdint>

#include "common/status.h"

namespace dg {

// Worst-case encoded size of `size` input bytes (without the trailing delimiter).
constexpr size_t cobs_max_encoded_size(size_t size) { return size + size / 254 + 1; }

// COBS over input that arrives in pieces (a frame's header, payload and CRC), so that no copy of
// the whole frame is needed on a device's stack: the same bytes as cobs_encode of the pieces'
// concatenation.
class CobsWriter {
 public:
  CobsWriter(uint8_t* out, size_t capacity) : out_(out), capacity_(capacity) {}
  void put(const uint8_t* in, size_t size);
  // Closes the last block. kOverflow when `capacity` was too small (nothing was written past it).
  Status finish(size_t* out_size);

 private:
  // Writes the open block's code byte in its place (or notes the overflow); close_block() then
  // opens the next block.
  void place_code();
  void close_block();
  uint8_t* out_;
  size_t capacity_;
  size_t code_index_ = 0;
  size_t write_ = 1;
  uint8_t code_ = 1;
  bool overflow_ = false;
};

// Encodes `in` into `out`; the result contains no zero byte. Returns kOverflow if
// `out_capacity` is too small.
Status cobs_encode(const uint8_t* in, size_t in_size, uint8_t* out, size_t out_capacity,
                   size_t* out_size);

// Decodes `in` (no delimiter) into `out`; `out` may equal `in` (decoding in place).
Status cobs_decode(const uint8_t* in, size_t in_size, uint8_t* out, size_t out_capacity,
                   size_t* out_size);

}  // namespace dg

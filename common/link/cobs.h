// Consistent Overhead Byte Stuffing: removes every zero byte so 0x00 can delimit frames.
#pragma once
#include <cstddef>
#include <cstdint>

#include "common/status.h"

namespace dg {

// Worst-case encoded size of `size` input bytes (without the trailing delimiter).
constexpr size_t cobs_max_encoded_size(size_t size) { return size + size / 254 + 1; }

// Encodes `in` into `out`; the result contains no zero byte. Returns kOverflow if
// `out_capacity` is too small.
Status cobs_encode(const uint8_t* in, size_t in_size, uint8_t* out, size_t out_capacity,
                   size_t* out_size);

// Decodes `in` (no delimiter) into `out`; `out` may equal `in` (decoding in place).
Status cobs_decode(const uint8_t* in, size_t in_size, uint8_t* out, size_t out_capacity,
                   size_t* out_size);

}  // namespace dg

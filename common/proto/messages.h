// Encoding and decoding of the Envelope message through nanopb, with status values.
#pragma once
#include <cstddef>
#include <cstdint>

#include "common/status.h"
#include "digitizer.pb.h"

namespace dg {

// Encodes `envelope`; kOverflow if it does not fit in `capacity` bytes.
Status encode_envelope(const digitizer_Envelope& envelope, uint8_t* out, size_t capacity,
                       size_t* out_size);

// Decodes bytes into `envelope` (cleared first). kBadEncoding for bytes that are
// not an Envelope within our size limits.
Status decode_envelope(const uint8_t* data, size_t size, digitizer_Envelope* envelope);

// Copies a C string into a fixed nanopb string field, truncating if needed.
template <size_t N>
void set_string(char (&field)[N], const char* text) {
  size_t i = 0;
  for (; text != nullptr && text[i] != '\0' && i + 1 < N; ++i) field[i] = text[i];
  field[i] = '\0';
}

}  // namespace dg

// Encoding and decoding of the Envelope message through nanopb, with status values.
#pragma once
#include <cstddef>
#include <cstdint>
#include <initializer_list>

#include "common/status.h"
#include "digitizer.pb.h"

namespace dg {

// The largest Envelope a host sends: its request id (a tag and a 5-byte varint) and the largest of
// the bodies a host sends, with their tag and a length of up to two bytes. A device's frame reader
// needs room for no more.
constexpr size_t kHostEnvelopeMaxSize = [] {
  size_t body = 0;
  for (size_t size : {size_t{digitizer_HostHello_size}, size_t{digitizer_ScanRequest_size}, size_t{digitizer_Command_size},
                      size_t{digitizer_PointAck_size}, size_t{digitizer_ResumeScan_size}}) {
    body = size > body ? size : body;
  }
  return 6 + 3 + body;
}();

// The largest Envelope a device sends other than a point batch (Hello, Status, FitResult, Fault,
// and the rest), counted as kHostEnvelopeMaxSize is: a device's frames must have room for it.
constexpr size_t kDeviceReplyMaxSize = [] {
  size_t body = 0;
  for (size_t size : {size_t{digitizer_Hello_size}, size_t{digitizer_Status_size}, size_t{digitizer_FitResult_size},
                      size_t{digitizer_Fault_size}, size_t{digitizer_Accepted_size}, size_t{digitizer_LineDone_size},
                      size_t{digitizer_ScanDone_size}, size_t{digitizer_Repeatability_size},
                      size_t{digitizer_TouchResult_size}}) {
    body = size > body ? size : body;
  }
  return 6 + 3 + body;
}();

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

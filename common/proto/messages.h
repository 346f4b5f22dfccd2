// Encoding and decoding of the Envelope message through nanopb, with status values.
#pragma once
#include <cstddef>
#include <cstdint>
#include <initializer_list>

#include "common/status.h"
#include "digitizer.pb.h"

namespace dg {

// The most bytes an Envelope can take whose body is at most the largest of `bodies` (nanopb's
// _size figures): its request id (a tag and a 5-byte varint), and the body with its tag and a
// length of up to two bytes.
constexpr size_t largest_envelope(std::initializer_list<size_t> bodies) {
  size_t body = 0;
  for (size_t size : bodies) body = size > body ? size : body;
  return 6 + 3 + body;
}

// The largest Envelope a host sends: a device's frame reader needs room for no more.
constexpr size_t kHostEnvelopeMaxSize =
    largest_envelope({digitizer_HostHello_size, digitizer_ScanRequest_size, digitizer_Command_size,
                      digitizer_PointAck_size, digitizer_ResumeScan_size});

// The largest Envelope a device sends other than a point batch: a device's frames must have room
// for it.
constexpr size_t kDeviceReplyMaxSize =
    largest_envelope({digitizer_Hello_size, digitizer_Status_size, digitizer_FitResult_size, digitizer_Fault_size,
                      digitizer_Accepted_size, digitizer_LineDone_size, digitizer_ScanDone_size,
                      digitizer_Repeatability_size, digitizer_TouchResult_size});

// Encodes `envelope`; kOverflow if it does not fit in `capacity` bytes.
Status encode_envelope(const digitizer_Envelope& envelope, uint8_t* out, size_t capacity,
                       size_t* out_size);

// Decodes bytes into `envelope` (cleared first). kBadEncoding for bytes that are
// not an Envelope within our size limits.
Status decode_envelope(const uint8_t* data, size_t size, digitizer_Envelope* envelope);

// A CalibrationSummary as the bytes a board stores (a nanopb message, so a later firmware reads
// an earlier one's), and back; kOverflow and kBadEncoding as for envelopes.
Status encode_calibration_summary(const digitizer_CalibrationSummary& summary, uint8_t* out, size_t capacity,
                                  size_t* out_size);
Status decode_calibration_summary(const uint8_t* data, size_t size, digitizer_CalibrationSummary* summary);

// Copies a C string into a fixed nanopb string field, truncating if needed.
template <size_t N>
void set_string(char (&field)[N], const char* text) {
  size_t i = 0;
  for (; text != nullptr && text[i] != '\0' && i + 1 < N; ++i) field[i] = text[i];
  field[i] = '\0';
}

}  // namespace dg

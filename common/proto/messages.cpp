// nanopb wrappers: the only place that calls pb_encode/pb_decode (Envelopes and the stored calibration summary).
#include "common/proto/messages.h"

#include <pb_decode.h>
#include <pb_encode.h>

#include "common/link/frame.h"

namespace dg {

static_assert(digitizer_Envelope_size <= kFrameMaxPayload,
              "an Envelope must fit in one frame payload");

namespace {

// The one encoder and decoder of a fixed-size nanopb message (no callbacks, no heap).
Status encode_fields(const pb_msgdesc_t* fields, const void* message, uint8_t* out, size_t capacity, size_t* out_size) {
  pb_ostream_t stream = pb_ostream_from_buffer(out, capacity);
  if (!pb_encode(&stream, fields, message)) return Status::kOverflow;
  *out_size = stream.bytes_written;
  return Status::kOk;
}

Status decode_fields(const pb_msgdesc_t* fields, const uint8_t* data, size_t size, void* message) {
  pb_istream_t stream = pb_istream_from_buffer(data, size);
  return pb_decode(&stream, fields, message) ? Status::kOk : Status::kBadEncoding;
}

}  // namespace

Status encode_envelope(const digitizer_Envelope& envelope, uint8_t* out, size_t capacity,
                       size_t* out_size) {
  return encode_fields(digitizer_Envelope_fields, &envelope, out, capacity, out_size);
}

Status decode_envelope(const uint8_t* data, size_t size, digitizer_Envelope* envelope) {
  *envelope = digitizer_Envelope_init_zero;
  return decode_fields(digitizer_Envelope_fields, data, size, envelope);
}

Status encode_calibration_summary(const digitizer_CalibrationSummary& summary, uint8_t* out, size_t capacity,
                                  size_t* out_size) {
  return encode_fields(digitizer_CalibrationSummary_fields, &summary, out, capacity, out_size);
}

Status decode_calibration_summary(const uint8_t* data, size_t size, digitizer_CalibrationSummary* summary) {
  *summary = digitizer_CalibrationSummary_init_zero;
  return decode_fields(digitizer_CalibrationSummary_fields, data, size, summary);
}

}  // namespace dg

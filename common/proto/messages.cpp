// nanopb wrappers: the only place that calls pb_encode/pb_decode on Envelopes.
#include "common/proto/messages.h"

#include <pb_decode.h>
#include <pb_encode.h>

#include "common/link/frame.h"

namespace dg {

static_assert(digitizer_Envelope_size <= kFrameMaxPayload,
              "an Envelope must fit in one frame payload");

Status encode_envelope(const digitizer_Envelope& envelope, uint8_t* out, size_t capacity,
                       size_t* out_size) {
  pb_ostream_t stream = pb_ostream_from_buffer(out, capacity);
  if (!pb_encode(&stream, digitizer_Envelope_fields, &envelope)) return Status::kOverflow;
  *out_size = stream.bytes_written;
  return Status::kOk;
}

Status decode_envelope(const uint8_t* data, size_t size, digitizer_Envelope* envelope) {
  *envelope = digitizer_Envelope_init_zero;
  pb_istream_t stream = pb_istream_from_buffer(data, size);
  if (!pb_decode(&stream, digitizer_Envelope_fields, envelope)) return Status::kBadEncoding;
  return Status::kOk;
}

}  // namespace dg

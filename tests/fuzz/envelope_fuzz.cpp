// Fuzzes the nanopb Envelope decoder and point-batch expansion with arbitrary bytes.
#include "common/proto/messages.h"
#include "common/proto/point_batch.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  digitizer_Envelope message;
  if (dg::decode_envelope(data, size, &message) != dg::Status::kOk) return 0;
  if (message.which_body == digitizer_Envelope_points_tag) {
    dg::PointSample points[dg::kMaxPointsPerBatch];
    size_t count = 0;
    dg::point_batch_expand(message.body.points, points, &count);
  }
  // What decoded must encode again.
  uint8_t buffer[digitizer_Envelope_size];
  size_t out = 0;
  if (dg::encode_envelope(message, buffer, sizeof(buffer), &out) != dg::Status::kOk) __builtin_trap();
  return 0;
}

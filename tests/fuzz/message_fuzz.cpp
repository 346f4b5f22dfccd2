// Fuzzes the nanopb decoder of every message type on its own (the first byte picks the type):
// what decodes must encode again, and a point batch must expand or be refused, never overrun.
#include <pb_decode.h>
#include <pb_encode.h>

#include "common/proto/point_batch.h"
#include "digitizer.pb.h"

namespace {

// Decodes into a zeroed message of the type and encodes it back.
template <typename Message>
void round_trip(const pb_msgdesc_t* fields, const uint8_t* data, size_t size) {
  Message message{};
  pb_istream_t in = pb_istream_from_buffer(data, size);
  if (!pb_decode(&in, fields, &message)) return;
  uint8_t buffer[digitizer_Envelope_size + digitizer_ScanRecord_size];
  pb_ostream_t out = pb_ostream_from_buffer(buffer, sizeof(buffer));
  if (!pb_encode(&out, fields, &message)) __builtin_trap();
  if constexpr (sizeof(Message) == sizeof(digitizer_PointBatch)) {
    dg::PointSample points[dg::kMaxPointsPerBatch];
    size_t count = 0;
    dg::point_batch_expand(*reinterpret_cast<const digitizer_PointBatch*>(&message), points, &count);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const uint8_t* body = data + 1;
  const size_t n = size - 1;
  switch (data[0] % 17) {
    case 0: round_trip<digitizer_HostHello>(digitizer_HostHello_fields, body, n); break;
    case 1: round_trip<digitizer_Hello>(digitizer_Hello_fields, body, n); break;
    case 2: round_trip<digitizer_ScanRequest>(digitizer_ScanRequest_fields, body, n); break;
    case 3: round_trip<digitizer_PointBatch>(digitizer_PointBatch_fields, body, n); break;
    case 4: round_trip<digitizer_LineDone>(digitizer_LineDone_fields, body, n); break;
    case 5: round_trip<digitizer_ScanDone>(digitizer_ScanDone_fields, body, n); break;
    case 6: round_trip<digitizer_Status>(digitizer_Status_fields, body, n); break;
    case 7: round_trip<digitizer_Fault>(digitizer_Fault_fields, body, n); break;
    case 8: round_trip<digitizer_Command>(digitizer_Command_fields, body, n); break;
    case 9: round_trip<digitizer_FitResult>(digitizer_FitResult_fields, body, n); break;
    case 10: round_trip<digitizer_PointAck>(digitizer_PointAck_fields, body, n); break;
    case 11: round_trip<digitizer_ResumeScan>(digitizer_ResumeScan_fields, body, n); break;
    case 12: round_trip<digitizer_Accepted>(digitizer_Accepted_fields, body, n); break;
    case 13: round_trip<digitizer_Range>(digitizer_Range_fields, body, n); break;
    case 14: round_trip<digitizer_Extent>(digitizer_Extent_fields, body, n); break;
    case 15: round_trip<digitizer_ScanRecord>(digitizer_ScanRecord_fields, body, n); break;
    default: round_trip<digitizer_Envelope>(digitizer_Envelope_fields, body, n); break;
  }
  return 0;
}

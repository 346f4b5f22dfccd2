// nanopb wrappers: the only place that calls pb_encode/pb_decode (Envelopes and the stored calibration summary).
#include "common/proto/messages.h"

#include <pb_decode.h>
#include <pb_encode.h>

#include <cstdint>
#include <cstring>

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

// Whether an enum field that nanopb decoded holds a value in its enum's range. nanopb stores
// whatever varint the sender wrote; read as the enum, a value beyond the enum's range is undefined
// behaviour (the host's session fuzzer sent a fault code of 30207, and the sanitizer stopped at the
// comparison), so the field's bytes are read as a signed integer of the same size instead.
template <typename E>
bool in_range(const E& field, E lowest, E highest) {
  int32_t value = 0;
  if constexpr (sizeof(E) == 1) {
    int8_t narrow;
    std::memcpy(&narrow, &field, 1);
    value = narrow;
  } else if constexpr (sizeof(E) == 2) {
    int16_t narrow;
    std::memcpy(&narrow, &field, 2);
    value = narrow;
  } else {
    static_assert(sizeof(E) == 4, "nanopb stores an enum in 1, 2 or 4 bytes");
    std::memcpy(&value, &field, 4);
  }
  return value >= static_cast<int32_t>(lowest) && value <= static_cast<int32_t>(highest);
}

// Every enum field of the envelope's body within its enum's range (the ones the protocol has).
bool enums_in_range(const digitizer_Envelope& e) {
  switch (e.which_body) {
    case digitizer_Envelope_scan_request_tag: {
      const digitizer_ScanRequest& r = e.body.scan_request;
      return in_range(r.pattern, _digitizer_ScanPattern_MIN, _digitizer_ScanPattern_MAX) &&
             in_range(r.probe, _digitizer_ProbeType_MIN, _digitizer_ProbeType_MAX) &&
             in_range(r.mode, _digitizer_ScanMode_MIN, _digitizer_ScanMode_MAX);
    }
    case digitizer_Envelope_scan_done_tag:
      return in_range(e.body.scan_done.reason, _digitizer_ScanEnd_MIN, _digitizer_ScanEnd_MAX);
    case digitizer_Envelope_status_tag: {
      const digitizer_Status& s = e.body.status;
      return in_range(s.state, _digitizer_DeviceState_MIN, _digitizer_DeviceState_MAX) &&
             in_range(s.alarm, _digitizer_FaultCode_MIN, _digitizer_FaultCode_MAX) &&
             in_range(s.reset_cause, _digitizer_ResetCause_MIN, _digitizer_ResetCause_MAX);
    }
    case digitizer_Envelope_fault_tag:
      return in_range(e.body.fault.code, _digitizer_FaultCode_MIN, _digitizer_FaultCode_MAX);
    case digitizer_Envelope_command_tag:
      return in_range(e.body.command.kind, _digitizer_CommandKind_MIN, _digitizer_CommandKind_MAX) &&
             in_range(e.body.command.fit_model, _digitizer_DeviceFitModel_MIN, _digitizer_DeviceFitModel_MAX);
    case digitizer_Envelope_fit_result_tag:
      return in_range(e.body.fit_result.model, _digitizer_DeviceFitModel_MIN, _digitizer_DeviceFitModel_MAX) &&
             in_range(e.body.fit_result.status, _digitizer_FitStatus_MIN, _digitizer_FitStatus_MAX);
    default:
      return true;
  }
}

}  // namespace

Status encode_envelope(const digitizer_Envelope& envelope, uint8_t* out, size_t capacity,
                       size_t* out_size) {
  return encode_fields(digitizer_Envelope_fields, &envelope, out, capacity, out_size);
}

Status decode_envelope(const uint8_t* data, size_t size, digitizer_Envelope* envelope) {
  *envelope = digitizer_Envelope_init_zero;
  const Status decoded = decode_fields(digitizer_Envelope_fields, data, size, envelope);
  if (decoded != Status::kOk) return decoded;
  // A value no enum of the protocol names is a damaged or foreign message, refused as one.
  if (!enums_in_range(*envelope)) {
    *envelope = digitizer_Envelope_init_zero;
    return Status::kBadEncoding;
  }
  return Status::kOk;
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

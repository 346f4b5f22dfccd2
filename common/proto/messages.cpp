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

// Every enum field of a message within its enum's range, derived from the field lists nanopb
// generates (digitizer.pb.h), so a field added to digitizer.proto is checked without a list kept
// here by hand. nanopb's run-time descriptors cannot do this: they do not tell an enum from an
// integer. A field type not named below (a float, a repeated enum) stops the build, so that a
// change of the protocol is decided here, not decoded unchecked.
#define DG_CAT3(a, b, c) a##b##c
#define DG_ENUM_BOUND(enum_type, end) DG_CAT3(_, enum_type, end)
#define DG_UNPACK(...) __VA_ARGS__
#define DG_APPLY(f, ...) f(__VA_ARGS__)
#define DG_FIELD_IN_RANGE(msg, allocation, holding, type, name, tag) \
  DG_HOLDING_##holding(msg, type, name, tag)
#define DG_HOLDING_SINGULAR(msg, type, name, tag) DG_TYPE_##type(msg, name)
#define DG_HOLDING_OPTIONAL(msg, type, name, tag) DG_TYPE_##type(msg, name)
#define DG_HOLDING_ONEOF(msg, type, name, tag) DG_APPLY(DG_ONEOF_IN_RANGE, DG_UNPACK name, tag)
#define DG_ONEOF_IN_RANGE(union_name, member, path, tag) \
  &&(m.which_##union_name != (tag) || enums_in_range(m.path))
#define DG_TYPE_UENUM(msg, name) \
  &&in_range(m.name, DG_ENUM_BOUND(msg##_##name##_ENUMTYPE, _MIN), DG_ENUM_BOUND(msg##_##name##_ENUMTYPE, _MAX))
#define DG_TYPE_ENUM(msg, name) DG_TYPE_UENUM(msg, name)
#define DG_TYPE_MESSAGE(msg, name) &&enums_in_range(m.name)
#define DG_TYPE_BOOL(msg, name)
#define DG_TYPE_UINT32(msg, name)
#define DG_TYPE_SINT32(msg, name)
#define DG_TYPE_UINT64(msg, name)
#define DG_TYPE_FIXED32(msg, name)
#define DG_TYPE_STRING(msg, name)
#define DG_HOLDING_REPEATED(msg, type, name, tag) DG_REPEATED_##type
#define DG_REPEATED_SINT32
#define DG_REPEATED_UINT32
#define DG_ENUMS_IN_RANGE_OF(msg) \
  bool enums_in_range([[maybe_unused]] const msg& m) { return true msg##_FIELDLIST(DG_FIELD_IN_RANGE, msg); }

// In the order of use: a message before the messages that hold it. One left out stops the build.
DG_ENUMS_IN_RANGE_OF(digitizer_CalibrationSummary)
DG_ENUMS_IN_RANGE_OF(digitizer_Range)
DG_ENUMS_IN_RANGE_OF(digitizer_Extent)
DG_ENUMS_IN_RANGE_OF(digitizer_HostHello)
DG_ENUMS_IN_RANGE_OF(digitizer_Hello)
DG_ENUMS_IN_RANGE_OF(digitizer_ScanRequest)
DG_ENUMS_IN_RANGE_OF(digitizer_PointBatch)
DG_ENUMS_IN_RANGE_OF(digitizer_LineDone)
DG_ENUMS_IN_RANGE_OF(digitizer_ScanDone)
DG_ENUMS_IN_RANGE_OF(digitizer_Status)
DG_ENUMS_IN_RANGE_OF(digitizer_Fault)
DG_ENUMS_IN_RANGE_OF(digitizer_Command)
DG_ENUMS_IN_RANGE_OF(digitizer_TouchResult)
DG_ENUMS_IN_RANGE_OF(digitizer_Repeatability)
DG_ENUMS_IN_RANGE_OF(digitizer_FitResult)
DG_ENUMS_IN_RANGE_OF(digitizer_PointAck)
DG_ENUMS_IN_RANGE_OF(digitizer_ResumeScan)
DG_ENUMS_IN_RANGE_OF(digitizer_Accepted)
DG_ENUMS_IN_RANGE_OF(digitizer_Envelope)

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

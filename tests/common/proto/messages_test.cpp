// Envelopes through nanopb: every field survives, garbage is refused.
#include "common/proto/messages.h"

#include <CppUTest/TestHarness.h>

#include <cstdint>
#include <cstring>

TEST_GROUP(Messages){};

TEST(Messages, HelloRoundTrips) {
  digitizer_Envelope out = digitizer_Envelope_init_zero;
  out.id = 42;
  out.which_body = digitizer_Envelope_hello_tag;
  digitizer_Hello& h = out.body.hello;
  h.protocol_version = 1;
  h.min_protocol_version = 1;
  dg::set_string(h.firmware_version, "1.2.3");
  dg::set_string(h.device_id, "DG-1234");
  dg::set_string(h.board, "stm32f411");
  h.capabilities = digitizer_Capability_CAP_DIGIMATIC | digitizer_Capability_CAP_TOUCH_PROBE;
  h.has_table = true;
  h.table.has_x = h.table.has_z = true;
  h.table.x.max_nm = 200000000;
  h.table.z.min_nm = -12500000;
  h.gauge_resolution_nm = 1000;
  uint8_t buffer[digitizer_Envelope_size];
  size_t size = 0;
  CHECK(dg::encode_envelope(out, buffer, sizeof(buffer), &size) == dg::Status::kOk);
  digitizer_Envelope in;
  CHECK(dg::decode_envelope(buffer, size, &in) == dg::Status::kOk);
  LONGS_EQUAL(42, in.id);
  LONGS_EQUAL(digitizer_Envelope_hello_tag, in.which_body);
  STRCMP_EQUAL("DG-1234", in.body.hello.device_id);
  STRCMP_EQUAL("stm32f411", in.body.hello.board);
  LONGS_EQUAL(200000000, in.body.hello.table.x.max_nm);
  LONGS_EQUAL(-12500000, in.body.hello.table.z.min_nm);
  LONGS_EQUAL(h.capabilities, in.body.hello.capabilities);
}

TEST(Messages, ScanRequestRoundTrips) {
  digitizer_Envelope out = digitizer_Envelope_init_zero;
  out.which_body = digitizer_Envelope_scan_request_tag;
  digitizer_ScanRequest& r = out.body.scan_request;
  r.has_x = r.has_y = true;
  r.x.min_nm = -5000000;
  r.x.max_nm = 40000000;
  r.y.max_nm = 30000000;
  r.step_x_nm = r.step_y_nm = 1000000;
  r.pattern = digitizer_ScanPattern_PATTERN_SERPENTINE;
  r.samples_per_point = 3;
  uint8_t buffer[digitizer_Envelope_size];
  size_t size = 0;
  CHECK(dg::encode_envelope(out, buffer, sizeof(buffer), &size) == dg::Status::kOk);
  digitizer_Envelope in;
  CHECK(dg::decode_envelope(buffer, size, &in) == dg::Status::kOk);
  CHECK(std::memcmp(&in.body.scan_request, &r, sizeof(r)) == 0);
}

TEST(Messages, LongStringsAreTruncatedNotOverflowed) {
  char field[8];
  dg::set_string(field, "a string longer than the field");
  STRCMP_EQUAL("a strin", field);
}

TEST(Messages, RejectsAnEnumValueTheProtocolDoesNotName) {
  // A fault code of 30207 on the wire (what the session fuzzer sent): read as the enum it would be
  // undefined behaviour, so the envelope is refused as badly encoded. Written into the field by
  // its bytes, as the wire would carry it.
  digitizer_Envelope out = digitizer_Envelope_init_zero;
  out.which_body = digitizer_Envelope_fault_tag;
  const int32_t foreign = 30207;
  static_assert(sizeof out.body.fault.code == sizeof foreign, "a 32-bit enum");
  std::memcpy(&out.body.fault.code, &foreign, sizeof foreign);
  uint8_t buffer[digitizer_Envelope_size];
  size_t size = 0;
  CHECK(dg::encode_envelope(out, buffer, sizeof buffer, &size) == dg::Status::kOk);
  digitizer_Envelope in;
  CHECK(dg::decode_envelope(buffer, size, &in) == dg::Status::kBadEncoding);
  // The largest code the protocol names still passes.
  out.body.fault.code = digitizer_FaultCode_FAULT_NOT_HOMED;
  CHECK(dg::encode_envelope(out, buffer, sizeof buffer, &size) == dg::Status::kOk);
  CHECK(dg::decode_envelope(buffer, size, &in) == dg::Status::kOk);
  CHECK(in.body.fault.code == digitizer_FaultCode_FAULT_NOT_HOMED);
}

namespace {

bool decodes(const digitizer_Envelope& out) {
  uint8_t buffer[digitizer_Envelope_size];
  size_t size = 0;
  if (dg::encode_envelope(out, buffer, sizeof buffer, &size) != dg::Status::kOk) return false;
  digitizer_Envelope in;
  return dg::decode_envelope(buffer, size, &in) == dg::Status::kOk;
}

// One enum field of an envelope: its enum's largest value decodes, the value past it is refused.
// The field is left at the largest value, so the next field of the same message is tested alone.
template <typename E>
void check_bounded(const digitizer_Envelope& envelope, E* field, E highest) {
  const int32_t beyond = static_cast<int32_t>(highest) + 1;
  static_assert(sizeof(E) == sizeof beyond, "a 32-bit enum");
  std::memcpy(field, &beyond, sizeof beyond);
  CHECK_TEXT(!decodes(envelope), "a value past the enum decodes");
  *field = highest;
  CHECK_TEXT(decodes(envelope), "the largest named value is refused");
}

}  // namespace

TEST(Messages, EveryEnumFieldOfTheProtocolIsBounded) {
  // The twelve enum fields of digitizer.proto, each in its message (the decoder's check is
  // derived from nanopb's field lists; this is the list the protocol's author would write).
  digitizer_Envelope e = digitizer_Envelope_init_zero;
  e.which_body = digitizer_Envelope_scan_request_tag;
  check_bounded(e, &e.body.scan_request.pattern, _digitizer_ScanPattern_MAX);
  check_bounded(e, &e.body.scan_request.probe, _digitizer_ProbeType_MAX);
  check_bounded(e, &e.body.scan_request.mode, _digitizer_ScanMode_MAX);
  e = digitizer_Envelope_init_zero;
  e.which_body = digitizer_Envelope_scan_done_tag;
  check_bounded(e, &e.body.scan_done.reason, _digitizer_ScanEnd_MAX);
  e = digitizer_Envelope_init_zero;
  e.which_body = digitizer_Envelope_status_tag;
  check_bounded(e, &e.body.status.state, _digitizer_DeviceState_MAX);
  check_bounded(e, &e.body.status.alarm, _digitizer_FaultCode_MAX);
  check_bounded(e, &e.body.status.reset_cause, _digitizer_ResetCause_MAX);
  e = digitizer_Envelope_init_zero;
  e.which_body = digitizer_Envelope_fault_tag;
  check_bounded(e, &e.body.fault.code, _digitizer_FaultCode_MAX);
  e = digitizer_Envelope_init_zero;
  e.which_body = digitizer_Envelope_command_tag;
  check_bounded(e, &e.body.command.kind, _digitizer_CommandKind_MAX);
  check_bounded(e, &e.body.command.fit_model, _digitizer_DeviceFitModel_MAX);
  e = digitizer_Envelope_init_zero;
  e.which_body = digitizer_Envelope_fit_result_tag;
  check_bounded(e, &e.body.fit_result.model, _digitizer_DeviceFitModel_MAX);
  check_bounded(e, &e.body.fit_result.status, _digitizer_FitStatus_MAX);
}

TEST(Messages, RejectsGarbage) {
  const uint8_t garbage[] = {0x2A, 0xFF, 0xFF, 0xFF, 0xFF, 0x0F, 0x01};
  digitizer_Envelope in;
  CHECK(dg::decode_envelope(garbage, sizeof(garbage), &in) == dg::Status::kBadEncoding);
}

TEST(Messages, RejectsAStringLongerThanItsLimit) {
  // Envelope.fault (field 9) holding a Fault.detail (field 2, at most 64 bytes) of 100 bytes.
  uint8_t bytes[128] = {0x4A, 102, 0x12, 100};
  for (int i = 4; i < 104; ++i) bytes[i] = 'x';
  digitizer_Envelope in;
  CHECK(dg::decode_envelope(bytes, 104, &in) == dg::Status::kBadEncoding);
}

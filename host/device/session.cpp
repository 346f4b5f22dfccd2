// Session: the host end of the frame link and the version check of the first exchange.
#include "host/device/session.h"

#include <chrono>

#include "common/proto/messages.h"

namespace dg::host {

const char* fault_name(digitizer_FaultCode code) {
  switch (code) {
    case digitizer_FaultCode_FAULT_NONE: return "none";
    case digitizer_FaultCode_FAULT_BAD_REQUEST: return "bad request";
    case digitizer_FaultCode_FAULT_SOFT_LIMIT: return "soft limit";
    case digitizer_FaultCode_FAULT_HARD_LIMIT: return "hard limit";
    case digitizer_FaultCode_FAULT_PROBE_TIMEOUT: return "probe timeout";
    case digitizer_FaultCode_FAULT_PROBE_FRAME: return "probe frame invalid";
    case digitizer_FaultCode_FAULT_ESTOP: return "emergency stop";
    case digitizer_FaultCode_FAULT_BUSY: return "busy";
    case digitizer_FaultCode_FAULT_ALARM_LOCKED: return "alarm locked";
    case digitizer_FaultCode_FAULT_UNSUPPORTED: return "unsupported";
    case digitizer_FaultCode_FAULT_BAD_FRAME: return "bad frame";
    case digitizer_FaultCode_FAULT_VERSION: return "protocol version";
    case digitizer_FaultCode_FAULT_NOT_HOMED: return "not homed";
  }
  return "unknown fault";
}

Session::Session(Transport& transport) : transport_(transport), name_(transport.describe()) {}

uint32_t Session::send(digitizer_Envelope& message) {
  if (message.id == 0) message.id = next_id_++;
  uint8_t payload[kFrameMaxPayload];
  size_t payload_size = 0;
  if (encode_envelope(message, payload, sizeof(payload), &payload_size) != Status::kOk) {
    throw DeviceError(name_ + ": message too large to encode");
  }
  FrameHeader header;
  header.seq = ++tx_seq_;
  header.ack = rx_seq_;
  uint8_t wire[kFrameMaxWire];
  size_t wire_size = 0;
  if (frame_encode(header, payload, payload_size, wire, sizeof(wire), &wire_size) != Status::kOk) {
    throw DeviceError(name_ + ": cannot frame message");
  }
  transport_.write(wire, wire_size);
  bytes_out_ += wire_size;
  return message.id;
}

bool Session::receive(digitizer_Envelope* message, int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    while (pending_offset_ < pending_size_) {
      size_t used = 0;
      const Status status =
          decoder_.feed(pending_ + pending_offset_, pending_size_ - pending_offset_, &used);
      pending_offset_ += used;
      if (status != Status::kOk) continue;  // kNeedMore or a damaged frame (counted)
      rx_seq_ = decoder_.header().seq;
      if (decoder_.header().kind != FrameKind::kData) continue;
      // A frame with a good CRC whose message does not decode came from a sender
      // with another message set; it is skipped like a damaged frame.
      if (decode_envelope(decoder_.payload(), decoder_.payload_size(), message) != Status::kOk) {
        continue;
      }
      return true;
    }
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) return false;
    const int wait_ms = static_cast<int>(
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now).count());
    pending_size_ = transport_.read(pending_, sizeof(pending_), wait_ms > 0 ? wait_ms : 1);
    pending_offset_ = 0;
    bytes_in_ += pending_size_;
  }
}

digitizer_Hello Session::hello(int timeout_ms) {
  digitizer_Envelope request = digitizer_Envelope_init_zero;
  request.which_body = digitizer_Envelope_host_hello_tag;
  request.body.host_hello.protocol_version = digitizer_ProtocolVersion_PROTOCOL_VERSION;
  request.body.host_hello.min_protocol_version = digitizer_ProtocolVersion_PROTOCOL_VERSION;
  set_string(request.body.host_hello.host_version, DIGITIZER_VERSION);
  const uint32_t id = send(request);
  digitizer_Envelope reply;
  bool version_fault = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (std::chrono::steady_clock::now() < deadline) {
    const int left = static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(
                                          deadline - std::chrono::steady_clock::now())
                                          .count());
    if (!receive(&reply, left > 0 ? left : 1)) break;
    if (reply.id != id) continue;
    if (reply.which_body == digitizer_Envelope_fault_tag &&
        reply.body.fault.code == digitizer_FaultCode_FAULT_VERSION) {
      version_fault = true;
      continue;
    }
    if (reply.which_body != digitizer_Envelope_hello_tag) continue;
    const digitizer_Hello& h = reply.body.hello;
    if (version_fault || h.protocol_version < digitizer_ProtocolVersion_PROTOCOL_VERSION ||
        h.min_protocol_version > digitizer_ProtocolVersion_PROTOCOL_VERSION) {
      throw DeviceError(name_ + ": device speaks protocol " + std::to_string(h.min_protocol_version) +
                        ".." + std::to_string(h.protocol_version) + ", this host speaks " +
                        std::to_string(digitizer_ProtocolVersion_PROTOCOL_VERSION) +
                        "; update the " +
                        (h.protocol_version < digitizer_ProtocolVersion_PROTOCOL_VERSION
                             ? "device firmware"
                             : "host software"));
    }
    return h;
  }
  throw DeviceError(name_ + ": no answer to hello within " + std::to_string(timeout_ms) + " ms");
}

}  // namespace dg::host

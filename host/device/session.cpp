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

std::string capability_names(uint32_t bits) {
  static const struct {
    uint32_t bit;
    const char* name;
  } kNames[] = {{digitizer_Capability_CAP_DIGIMATIC, "Digimatic gauge"},
                {digitizer_Capability_CAP_CALIPER_24BIT, "24-bit caliper"},
                {digitizer_Capability_CAP_TOUCH_PROBE, "touch probe"},
                {digitizer_Capability_CAP_HOMING, "homing"},
                {digitizer_Capability_CAP_DEVICE_FIT, "device fit"},
                {digitizer_Capability_CAP_SIMULATED, "simulated"},
                {digitizer_Capability_CAP_RESUME, "resume"}};
  std::string names;
  for (const auto& n : kNames) {
    if ((bits & n.bit) == 0) continue;
    if (!names.empty()) names += ", ";
    names += n.name;
    bits &= ~n.bit;
  }
  if (bits != 0) names += (names.empty() ? "" : ", ") + std::string("unknown bits ") + std::to_string(bits);
  return names;
}

void Session::reopen() {
  transport_.reconnect();
  decoder_.reset();
  inbox_.clear();
  kept_.clear();
  pending_size_ = pending_offset_ = 0;
}

Session::Session(Transport& transport) : transport_(transport), name_(transport.describe()) {}

namespace {

// A device's window is a handful of frames (Hello does not say how many); 64 covers any.
constexpr int16_t kMaxKeptAhead = 64;

uint64_t now_us() {
  return static_cast<uint64_t>(
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch()).count());
}

}  // namespace

void Session::transmit() {
  uint8_t wire[kFrameMaxWire];
  size_t wire_size = 0;
  while (link_.next_frame(now_us(), wire, sizeof(wire), &wire_size)) {
    transport_.write(wire, wire_size);
  }
}

bool Session::pump(int wait_ms) {
  transmit();
  if (pending_offset_ >= pending_size_) {
    pending_size_ = transport_.read(pending_, sizeof(pending_), wait_ms > 0 ? wait_ms : 1);
    pending_offset_ = 0;
    bytes_in_ += pending_size_;
    if (pending_size_ == 0) return false;
  }
  while (pending_offset_ < pending_size_) {
    size_t used = 0;
    const Status status = decoder_.feed(pending_ + pending_offset_, pending_size_ - pending_offset_, &used);
    pending_offset_ += used;
    if (status != Status::kOk) continue;  // kNeedMore or a damaged frame (counted)
    if (!link_.receive(decoder_.header(), now_us())) {
      keep_ahead(decoder_.header(), decoder_.payload(), decoder_.payload_size());
      continue;
    }
    deliver(decoder_.payload(), decoder_.payload_size());
    deliver_kept();
  }
  transmit();  // acknowledge promptly
  return true;
}

void Session::deliver(const uint8_t* payload, size_t size) {
  // A frame with a good CRC whose message does not decode came from a sender with another
  // message set; it is skipped like a damaged frame (the link has acknowledged it).
  digitizer_Envelope message;
  if (decode_envelope(payload, size, &message) == Status::kOk) inbox_.push_back(message);
}

void Session::keep_ahead(const FrameHeader& header, const uint8_t* payload, size_t size) {
  if (header.kind != FrameKind::kData) return;
  // Only frames a sender's window can hold ahead of the gap: anything farther is stale.
  const int16_t ahead = static_cast<int16_t>(header.seq - link_.expected_seq());
  if (ahead <= 0 || ahead > kMaxKeptAhead) return;
  kept_[header.seq].assign(payload, payload + size);
}

void Session::deliver_kept() {
  for (auto kept = kept_.find(link_.expected_seq()); kept != kept_.end(); kept = kept_.find(link_.expected_seq())) {
    link_.deliver_kept();
    deliver(kept->second.data(), kept->second.size());
    kept_.erase(kept);
  }
}

uint32_t Session::queue(digitizer_Envelope& message, bool sync) {
  if (message.id == 0) message.id = next_id_++;
  uint8_t payload[kFrameMaxPayload];
  size_t payload_size = 0;
  if (encode_envelope(message, payload, sizeof(payload), &payload_size) != Status::kOk) {
    throw DeviceError(name_ + ": message too large to encode");
  }
  if (sync) {
    kept_.clear();  // frames of the old session
    // A session id from the clock: different from the last session's, never 0.
    const uint16_t id = static_cast<uint16_t>(now_us() % 65535 + 1);
    link_.send_sync(payload, payload_size, now_us(), id);
  } else {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (link_.send(payload, payload_size, now_us()) == Status::kBusy) {
      if (std::chrono::steady_clock::now() > deadline) {
        throw DeviceError(name_ + ": the device acknowledged nothing for 10 s; the link is down");
      }
      pump(5);
    }
  }
  transmit();
  return message.id;
}

uint32_t Session::send(digitizer_Envelope& message) { return queue(message, false); }

bool Session::receive(digitizer_Envelope* message, int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    if (!inbox_.empty()) {
      *message = inbox_.front();
      inbox_.pop_front();
      return true;
    }
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) return false;
    int wait_ms = static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now).count());
    // Wake for the retransmission timer as well.
    const uint64_t resend = link_.next_deadline_us(UINT64_MAX);
    if (resend != UINT64_MAX) {
      const uint64_t t = now_us();
      const int until_resend = resend > t ? static_cast<int>((resend - t) / 1000) + 1 : 1;
      if (until_resend < wait_ms) wait_ms = until_resend;
    }
    pump(wait_ms);
  }
}

bool Session::flush(int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (!link_.all_acknowledged() && std::chrono::steady_clock::now() < deadline) pump(5);
  transmit();
  return link_.all_acknowledged();
}

digitizer_Hello Session::hello(int timeout_ms, uint32_t required_capabilities) {
  digitizer_Envelope request = digitizer_Envelope_init_zero;
  request.which_body = digitizer_Envelope_host_hello_tag;
  request.body.host_hello.protocol_version = digitizer_ProtocolVersion_PROTOCOL_VERSION;
  request.body.host_hello.min_protocol_version = digitizer_ProtocolVersion_PROTOCOL_VERSION;
  set_string(request.body.host_hello.host_version, DIGITIZER_VERSION);
  request.body.host_hello.required_capabilities = required_capabilities;
  inbox_.clear();
  const uint32_t id = queue(request, true);
  digitizer_Envelope reply;
  bool version_fault = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (std::chrono::steady_clock::now() < deadline) {
    const int left = static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(
                                          deadline - std::chrono::steady_clock::now())
                                          .count());
    if (!receive(&reply, left > 0 ? left : 1)) break;
    if (reply.id != id) continue;
    if (reply.which_body == digitizer_Envelope_fault_tag) {
      // A version fault comes before the Hello that says which versions the device speaks; a
      // capability fault is judged from the Hello's capability bits.
      version_fault = version_fault || reply.body.fault.code == digitizer_FaultCode_FAULT_VERSION;
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
    const uint32_t missing = required_capabilities & ~h.capabilities;
    if (missing != 0) {
      throw DeviceError(name_ + ": device " + h.device_id + " (firmware " + h.firmware_version +
                        ") cannot do what this command needs: " + capability_names(missing) +
                        "; update the device firmware");
    }
    return h;
  }
  throw DeviceError(name_ + ": no answer to hello within " + std::to_string(timeout_ms) + " ms");
}

}  // namespace dg::host

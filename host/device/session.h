// A session with a device: frames and messages over a transport, and the hello exchange.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>

#include <deque>
#include <map>
#include <vector>

#include "common/link/frame.h"
#include "common/link/reliable_link.h"
#include "digitizer.pb.h"
#include "host/transport/transport.h"

namespace dg::host {

// The device refused, faulted, went silent or speaks another protocol version.
class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

const char* fault_name(digitizer_FaultCode code);
// The names of the Capability bits in `bits`, comma-separated ("resume, device fit").
std::string capability_names(uint32_t bits);

class Session {
 public:
  explicit Session(Transport& transport);

  // Opens a link session (a sync frame with a fresh id) and identifies the device; throws
  // DeviceError when versions cannot talk, the device lacks a `required` Capability bit, or it is
  // silent.
  digitizer_Hello hello(int timeout_ms, uint32_t required_capabilities = 0);
  // After a pulled cable: reconnects the transport (TransportError while the device is not back)
  // and forgets the old link's bytes. Call hello() next.
  void reopen();
  bool reconnectable() const { return transport_.reconnectable(); }
  // Sends a message through the reliable link; gives it a fresh request id if it has none. Waits
  // (reading, and keeping what arrives) while the window is full. Returns the id.
  uint32_t send(digitizer_Envelope& message);
  // Waits up to timeout_ms for the next message; false on timeout. Retransmissions and
  // acknowledgements go out while it waits.
  bool receive(digitizer_Envelope* message, int timeout_ms);

  // Waits up to timeout_ms until the device has acknowledged every frame sent; true when it has.
  // A host that ends a scan calls it so its last PointAck arrives (else the device keeps those
  // points in its ring and offers them to the next session).
  bool flush(int timeout_ms);

  uint64_t bytes_received() const { return bytes_in_; }
  const std::string& device_name() const { return name_; }
  // Frames that arrived whole (their CRC held), whatever they carried, and frames that arrived
  // damaged: a device whose frames arrive is alive, even when none of them brings a new message.
  uint32_t frames_whole() const { return decoder_.counters().frames; }
  uint32_t frames_damaged() const { return decoder_.counters().bad_crc + decoder_.counters().bad_encoding; }

 private:
  Transport& transport_;
  FrameDecoder decoder_;
  std::string name_;
  // Puts every due frame on the wire (new, resent, acks).
  void transmit();
  // Reads for up to wait_ms and hands in-order messages to the inbox; false when nothing came.
  bool pump(int wait_ms);
  uint32_t queue(digitizer_Envelope& message, bool sync);
  // Decodes a delivered payload into the inbox.
  void deliver(const uint8_t* payload, size_t size);
  // Keeps a data frame that came ahead of a gap, and hands up the kept frames the gap's filling
  // makes next: on a line that damages frames, those after a lost one need not be sent again.
  void keep_ahead(const FrameHeader& header, const uint8_t* payload, size_t size);
  void deliver_kept();

  ReliableLink<8> link_{50000};
  std::deque<digitizer_Envelope> inbox_;
  std::map<uint16_t, std::vector<uint8_t>> kept_;  // frames ahead of a gap, by sequence number
  uint8_t pending_[512] = {};
  size_t pending_size_ = 0, pending_offset_ = 0;
  uint32_t next_id_ = 1;
  uint64_t bytes_in_ = 0;
};

}  // namespace dg::host

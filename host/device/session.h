// A session with a device: frames and messages over a transport, and the hello exchange.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>

#include "common/link/frame.h"
#include "digitizer.pb.h"
#include "host/transport/transport.h"

namespace dg::host {

// The device refused, faulted, went silent or speaks another protocol version.
class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

const char* fault_name(digitizer_FaultCode code);

class Session {
 public:
  explicit Session(Transport& transport);

  // Identifies the device; throws DeviceError when versions cannot talk or it is silent.
  digitizer_Hello hello(int timeout_ms);
  // Sends a message; gives it a fresh request id if it has none. Returns the id.
  uint32_t send(digitizer_Envelope& message);
  // Waits up to timeout_ms for the next message; false on timeout.
  bool receive(digitizer_Envelope* message, int timeout_ms);

  uint64_t bytes_received() const { return bytes_in_; }
  uint64_t bytes_sent() const { return bytes_out_; }
  const FrameDecoder::Counters& frame_counters() const { return decoder_.counters(); }
  const std::string& device_name() const { return name_; }

 private:
  Transport& transport_;
  FrameDecoder decoder_;
  std::string name_;
  uint8_t pending_[512] = {};
  size_t pending_size_ = 0, pending_offset_ = 0;
  uint16_t tx_seq_ = 0, rx_seq_ = 0;
  uint32_t next_id_ = 1;
  uint64_t bytes_in_ = 0, bytes_out_ = 0;
};

}  // namespace dg::host

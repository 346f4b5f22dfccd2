// One interface for every way of reaching a device (sim:, usb:, unix:, tcp:, fault:).
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

namespace dg::host {

// A transport failed or the device went away; the message says which and why.
class TransportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Transport {
 public:
  virtual ~Transport() = default;
  // Writes all bytes or throws TransportError.
  virtual void write(const uint8_t* data, size_t size) = 0;
  // Reads what is available, waiting up to `timeout_ms`; returns 0 on timeout.
  // Throws TransportError when the device is gone.
  virtual size_t read(uint8_t* data, size_t capacity, int timeout_ms) = 0;
  // The URI it was opened with, for messages.
  virtual std::string describe() const = 0;
  // True when the device outlives this link (a USB device, a socket server), so that after a
  // pulled cable reconnect() can reach the same device again; false for the sim: child process.
  virtual bool reconnectable() const { return false; }
  // Closes the link, if open, and opens it again; throws TransportError while the device is not
  // back. Only for reconnectable() transports.
  virtual void reconnect() { throw TransportError(describe() + ": this transport cannot reconnect"); }
  // Closes the link as a pulled cable would (the device sees it go); reads and writes then throw.
  virtual void disconnect() {}
};

// Opens a device URI. Throws std::invalid_argument for a URI it cannot parse and
// TransportError when the device cannot be reached.
std::unique_ptr<Transport> open_transport(const std::string& uri);

}  // namespace dg::host

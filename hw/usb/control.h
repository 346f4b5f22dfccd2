// USB 2.0 chapter 9 on endpoint 0: the standard requests and the Microsoft OS 2.0 vendor request,
// decided here once, portable; a controller driver moves the bytes and does what it is told.
#pragma once
#include <cstddef>
#include <cstdint>

namespace dg::usb {

// The eight bytes of a SETUP packet (USB 2.0 9.3).
struct Setup {
  uint8_t request_type = 0;  // bmRequestType
  uint8_t request = 0;       // bRequest
  uint16_t value = 0;
  uint16_t index = 0;
  uint16_t length = 0;
};
Setup parse_setup(const uint8_t bytes[8]);

// What a request makes the controller do.
class EndpointControl {
 public:
  virtual ~EndpointControl() = default;
  // Called as SET_ADDRESS arrives; the driver knows whether its core wants the address before or
  // after the status stage.
  virtual void set_address(uint8_t address) = 0;
  // Opens (true) or closes the bulk endpoints.
  virtual void set_configured(bool configured) = 0;
  // Halts or un-halts a bulk endpoint; un-halting also resets its data toggle to DATA0.
  virtual void set_halt(uint8_t endpoint_address, bool halt) = 0;
  virtual bool halted(uint8_t endpoint_address) = 0;
};

struct ControlReply {
  enum Kind : uint8_t {
    kStall,   // a request error: the driver stalls the data or status stage
    kData,    // IN data stage with `data`, already cut to wLength, then a zero-length OUT status
    kNoData,  // no data stage: a zero-length IN status
  } kind = kStall;
  const uint8_t* data = nullptr;
  uint16_t size = 0;
};

class ControlRequests {
 public:
  // `serial` must outlive this object (the board's unique ID as text).
  ControlRequests(EndpointControl& controller, const char* serial) : controller_(controller), serial_(serial) {}

  ControlReply setup(const Setup& request);
  // A bus reset: the device returns to the default state.
  void bus_reset();
  uint8_t configuration() const { return configuration_; }

 private:
  ControlReply standard(const Setup& request);
  ControlReply get_descriptor(const Setup& request);
  ControlReply data(const uint8_t* bytes, size_t size, uint16_t length);
  bool endpoint_exists(uint16_t address) const;

  EndpointControl& controller_;
  const char* serial_;
  uint8_t configuration_ = 0;
  uint8_t address_ = 0;
  uint8_t buffer_[64] = {};  // strings (up to 31 characters) and status replies are built here
};

}  // namespace dg::usb

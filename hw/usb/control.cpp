// Request decoding per USB 2.0 tables 9-2 to 9-6 and 9.4; a request the device does not support,
// or one not valid in its state, gets a stall (a "Request Error", 9.2.7).
#include "hw/usb/control.h"

#include "hw/usb/descriptors.h"

namespace dg::usb {

namespace {

enum Request : uint8_t {
  kGetStatus = 0,
  kClearFeature = 1,
  kSetFeature = 3,
  kSetAddress = 5,
  kGetDescriptor = 6,
  kGetConfiguration = 8,
  kSetConfiguration = 9,
  kGetInterface = 10,
  kSetInterface = 11,
};
constexpr uint16_t kEndpointHalt = 0;  // feature selector (table 9-6)

constexpr uint8_t kDirectionIn = 0x80;
constexpr uint8_t type_of(uint8_t request_type) { return (request_type >> 5) & 3; }  // 0 standard, 2 vendor
constexpr uint8_t recipient_of(uint8_t request_type) { return request_type & 0x1F; }  // 0 device, 1 interface, 2 endpoint

}  // namespace

Setup parse_setup(const uint8_t bytes[8]) {
  Setup s;
  s.request_type = bytes[0];
  s.request = bytes[1];
  s.value = static_cast<uint16_t>(bytes[2] | bytes[3] << 8);
  s.index = static_cast<uint16_t>(bytes[4] | bytes[5] << 8);
  s.length = static_cast<uint16_t>(bytes[6] | bytes[7] << 8);
  return s;
}

void ControlRequests::bus_reset() {
  if (configuration_ != 0) controller_.set_configured(false);
  configuration_ = 0;
  address_ = 0;
}

ControlReply ControlRequests::setup(const Setup& request) {
  switch (type_of(request.request_type)) {
    case 0:
      return standard(request);
    case 2:
      if (request.request_type == (kDirectionIn | 0x40) && request.request == kMsVendorCode &&
          request.index == kMsOs20DescriptorIndex) {
        const Bytes set = ms_os_20_descriptor_set();
        return data(set.data, set.size, request.length);
      }
      return {};
    default:
      return {};
  }
}

ControlReply ControlRequests::data(const uint8_t* bytes, size_t size, uint16_t length) {
  ControlReply reply;
  reply.kind = ControlReply::kData;
  reply.data = bytes;
  reply.size = static_cast<uint16_t>(size < length ? size : length);
  return reply;
}

bool ControlRequests::endpoint_exists(uint16_t address) const {
  if ((address & 0x7F) == 0) return true;  // endpoint 0, either direction
  return configuration_ != 0 && (address == kBulkOutEndpoint || address == kBulkInEndpoint);
}

ControlReply ControlRequests::standard(const Setup& request) {
  const bool in = (request.request_type & kDirectionIn) != 0;
  const uint8_t recipient = recipient_of(request.request_type);
  const ControlReply none{ControlReply::kNoData, nullptr, 0};
  switch (request.request) {
    case kGetStatus: {
      if (!in || request.value != 0) return {};
      buffer_[0] = buffer_[1] = 0;  // bus powered, no remote wake-up; interface: reserved zeros
      if (recipient == 1 && (configuration_ == 0 || request.index != kInterfaceNumber)) return {};
      if (recipient == 2) {
        if (!endpoint_exists(request.index)) return {};
        buffer_[0] = (request.index & 0x7F) != 0 && controller_.halted(static_cast<uint8_t>(request.index)) ? 1 : 0;
      }
      if (recipient > 2) return {};
      return data(buffer_, 2, request.length);
    }
    case kClearFeature:
    case kSetFeature: {
      // Remote wake-up and test mode are not supported; only an endpoint's halt is.
      if (in || recipient != 2 || request.value != kEndpointHalt || !endpoint_exists(request.index)) return {};
      if ((request.index & 0x7F) != 0) {
        controller_.set_halt(static_cast<uint8_t>(request.index), request.request == kSetFeature);
      }
      return none;
    }
    case kSetAddress:
      if (in || recipient != 0 || request.value > 127 || request.index != 0 || request.length != 0 ||
          configuration_ != 0) {
        return {};
      }
      address_ = static_cast<uint8_t>(request.value);
      controller_.set_address(address_);
      return none;
    case kGetDescriptor:
      if (!in) return {};
      return get_descriptor(request);
    case kGetConfiguration:
      if (!in || recipient != 0) return {};
      buffer_[0] = configuration_;
      return data(buffer_, 1, request.length);
    case kSetConfiguration: {
      if (in || recipient != 0 || address_ == 0) return {};
      if (request.value != 0 && request.value != kConfigurationValue) return {};
      const uint8_t next = static_cast<uint8_t>(request.value);
      // Setting a configuration again resets its endpoints (9.1.1.5): close, then open.
      if (configuration_ != 0) controller_.set_configured(false);
      configuration_ = next;
      if (configuration_ != 0) controller_.set_configured(true);
      return none;
    }
    case kGetInterface:
      if (!in || recipient != 1 || configuration_ == 0 || request.index != kInterfaceNumber) return {};
      buffer_[0] = 0;
      return data(buffer_, 1, request.length);
    case kSetInterface:
      // One alternate setting; selecting it resets the endpoints' halt and toggles (9.4.10).
      if (in || recipient != 1 || configuration_ == 0 || request.index != kInterfaceNumber || request.value != 0) {
        return {};
      }
      controller_.set_halt(kBulkOutEndpoint, false);
      controller_.set_halt(kBulkInEndpoint, false);
      return none;
    default:
      return {};
  }
}

ControlReply ControlRequests::get_descriptor(const Setup& request) {
  const uint8_t type = static_cast<uint8_t>(request.value >> 8);
  const uint8_t index = static_cast<uint8_t>(request.value & 0xFF);
  if (recipient_of(request.request_type) != 0) return {};
  Bytes bytes{nullptr, 0};
  switch (type) {
    case kDeviceDescriptor: bytes = device_descriptor(); break;
    case kConfigurationDescriptor:
      if (index != 0) return {};
      bytes = configuration_descriptor();
      break;
    case kBosDescriptor: bytes = bos_descriptor(); break;
    case kStringDescriptor: {
      const size_t size = string_descriptor(index, serial_, buffer_, sizeof(buffer_));
      if (size == 0) return {};
      return data(buffer_, size, request.length);
    }
    default:
      // Among others the device qualifier: a full-speed-only device answers it with a request
      // error (9.6.2).
      return {};
  }
  return data(bytes.data, bytes.size, request.length);
}

}  // namespace dg::usb

// The USB identity of a digitizer controller: device, configuration, string, BOS and Microsoft
// OS 2.0 descriptors for one vendor-class interface with a bulk OUT and a bulk IN endpoint.
// Shared by every board with a USB device port, so the host cannot tell them apart.
#pragma once
#include <cstddef>
#include <cstdint>

namespace dg::usb {

// The pid.codes test IDs the host looks for by default (host/transport/usb_transport.cpp).
constexpr uint16_t kVendorId = 0x1209;
constexpr uint16_t kProductId = 0x0001;
constexpr uint16_t kDeviceRelease = 0x0100;  // bcdDevice 1.00

constexpr uint8_t kMaxPacketSize0 = 64;
constexpr uint16_t kBulkPacketSize = 64;  // full speed's largest bulk packet
constexpr uint8_t kBulkOutEndpoint = 0x01;
constexpr uint8_t kBulkInEndpoint = 0x81;
constexpr uint8_t kInterfaceNumber = 0;
constexpr uint8_t kConfigurationValue = 1;

// bRequest of the vendor request that returns the MS OS 2.0 descriptor set (any value the device
// does not otherwise use; Windows reads it from the BOS descriptor).
constexpr uint8_t kMsVendorCode = 0x20;
constexpr uint16_t kMsOs20DescriptorIndex = 7;  // wIndex of that request (MS OS 2.0, table 8)

// The interface's name (string kInterfaceName), which the Linux-gadget board declares to FunctionFS.
constexpr char kInterfaceNameText[] = "digitizer link";

enum StringIndex : uint8_t { kLanguages = 0, kManufacturer = 1, kProduct = 2, kSerial = 3, kInterfaceName = 4 };

// Descriptor types (USB 2.0 table 9-5, and 0x0F/0x10 from the USB 2.0 LPM ECN).
enum DescriptorType : uint8_t {
  kDeviceDescriptor = 1,
  kConfigurationDescriptor = 2,
  kStringDescriptor = 3,
  kInterfaceDescriptor = 4,
  kEndpointDescriptor = 5,
  kDeviceQualifierDescriptor = 6,
  kBosDescriptor = 0x0F,
  kDeviceCapabilityDescriptor = 0x10,
};

struct Bytes {
  const uint8_t* data;
  uint16_t size;
};

Bytes device_descriptor();
Bytes configuration_descriptor();
Bytes bos_descriptor();
Bytes ms_os_20_descriptor_set();

// Writes string descriptor `index` (UTF-16LE) into `out`; `serial` is the board's serial number
// (ASCII). Returns the descriptor's length, 0 for an index the device does not have.
size_t string_descriptor(uint8_t index, const char* serial, uint8_t* out, size_t capacity);

}  // namespace dg::usb

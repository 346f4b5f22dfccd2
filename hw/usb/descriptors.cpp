// The descriptor bytes. Layouts: USB 2.0 chapter 9 (device 9.6.1, configuration 9.6.3,
// interface 9.6.5, endpoint 9.6.6, string 9.6.7), the LPM ECN's BOS descriptor, and
// Microsoft OS 2.0 Descriptors Specification tables 4, 10, 13 and 14.
#include "hw/usb/descriptors.h"

namespace dg::usb {

namespace {

constexpr uint8_t lo(uint16_t v) { return static_cast<uint8_t>(v & 0xFF); }
constexpr uint8_t hi(uint16_t v) { return static_cast<uint8_t>(v >> 8); }

// bcdUSB 2.01: a host asks for the BOS descriptor only from a device of 2.01 or later.
constexpr uint8_t kDevice[18] = {
    18, kDeviceDescriptor, lo(0x0201), hi(0x0201),
    0x00, 0x00, 0x00,  // class in the interface
    kMaxPacketSize0,   lo(kVendorId), hi(kVendorId), lo(kProductId), hi(kProductId),
    lo(kDeviceRelease), hi(kDeviceRelease), kManufacturer, kProduct, kSerial,
    1,  // configurations
};

constexpr uint16_t kConfigurationLength = 9 + 9 + 7 + 7;
constexpr uint8_t kConfiguration[kConfigurationLength] = {
    9, kConfigurationDescriptor, lo(kConfigurationLength), hi(kConfigurationLength),
    1,  // interfaces
    kConfigurationValue, 0,
    0x80,  // bus powered: the board's logic runs from USB; the drivers have their own supply
    50,    // 100 mA, in 2 mA units
    // The vendor-class interface the host claims.
    9, kInterfaceDescriptor, kInterfaceNumber, 0, 2, 0xFF, 0x00, 0x00, kInterfaceName,
    7, kEndpointDescriptor, kBulkOutEndpoint, 0x02, lo(kBulkPacketSize), hi(kBulkPacketSize), 0,
    7, kEndpointDescriptor, kBulkInEndpoint, 0x02, lo(kBulkPacketSize), hi(kBulkPacketSize), 0,
};

// "DeviceInterfaceGUIDs" and the interface GUID, as UTF-16LE with their terminators, written out
// at compile time from ASCII.
template <size_t N>
struct Utf16 {
  uint8_t bytes[N * 2] = {};
};
template <size_t N>
constexpr Utf16<N> utf16(const char (&text)[N]) {
  Utf16<N> out{};
  for (size_t i = 0; i < N; ++i) out.bytes[2 * i] = static_cast<uint8_t>(text[i]);
  return out;
}

constexpr auto kPropertyName = utf16("DeviceInterfaceGUIDs");
// REG_MULTI_SZ: the list ends with a second terminator. The GUID is this project's own.
constexpr auto kInterfaceGuid = utf16("{6F3C9A52-1D4B-4E8A-9C27-5B0E8D3F7A41}\0");
constexpr uint16_t kPropertyNameLength = sizeof(kPropertyName.bytes);
constexpr uint16_t kPropertyDataLength = sizeof(kInterfaceGuid.bytes);  // the GUID and two terminators
constexpr uint16_t kRegistryLength = 10 + kPropertyNameLength + kPropertyDataLength;
constexpr uint16_t kMsOsSetLength = 10 + 20 + kRegistryLength;

constexpr uint8_t kWindows81[4] = {0x00, 0x00, 0x03, 0x06};  // 0x06030000: the first with MS OS 2.0

struct MsOsSet {
  uint8_t bytes[kMsOsSetLength] = {};
};

constexpr MsOsSet make_ms_os_set() {
  MsOsSet set{};
  size_t n = 0;
  auto put16 = [&](uint16_t v) {
    set.bytes[n++] = lo(v);
    set.bytes[n++] = hi(v);
  };
  // Descriptor set header (table 10).
  put16(10);
  put16(0x00);  // MS_OS_20_SET_HEADER_DESCRIPTOR
  for (uint8_t b : kWindows81) set.bytes[n++] = b;
  put16(kMsOsSetLength);
  // Compatible ID (table 13): bind WinUSB, so Windows needs no driver install.
  put16(20);
  put16(0x03);  // MS_OS_20_FEATURE_COMPATBLE_ID
  const char winusb[8] = {'W', 'I', 'N', 'U', 'S', 'B', 0, 0};
  for (char c : winusb) set.bytes[n++] = static_cast<uint8_t>(c);
  n += 8;  // sub-compatible ID: none
  // Registry property (table 14): the interface GUID applications open the device by.
  put16(kRegistryLength);
  put16(0x04);  // MS_OS_20_FEATURE_REG_PROPERTY
  put16(0x07);  // REG_MULTI_SZ
  put16(kPropertyNameLength);
  for (uint8_t b : kPropertyName.bytes) set.bytes[n++] = b;
  put16(kPropertyDataLength);
  for (size_t i = 0; i < kPropertyDataLength; ++i) set.bytes[n++] = kInterfaceGuid.bytes[i];
  return set;
}

constexpr MsOsSet kMsOsSet = make_ms_os_set();

constexpr uint16_t kBosLength = 5 + 28;
constexpr uint8_t kBos[kBosLength] = {
    5, kBosDescriptor, lo(kBosLength), hi(kBosLength), 1,
    // Platform capability (MS OS 2.0 table 4), UUID D8DD60DF-4589-4CC7-9CD2-659D9E648A9F as
    // stored (its first three fields little-endian).
    28, kDeviceCapabilityDescriptor, 0x05, 0x00,
    0xDF, 0x60, 0xDD, 0xD8, 0x89, 0x45, 0xC7, 0x4C, 0x9C, 0xD2, 0x65, 0x9D, 0x9E, 0x64, 0x8A, 0x9F,
    kWindows81[0], kWindows81[1], kWindows81[2], kWindows81[3],
    lo(kMsOsSetLength), hi(kMsOsSetLength), kMsVendorCode,
    0,  // no alternate enumeration
};

}  // namespace

Bytes device_descriptor() { return {kDevice, sizeof(kDevice)}; }
Bytes configuration_descriptor() { return {kConfiguration, sizeof(kConfiguration)}; }
Bytes bos_descriptor() { return {kBos, sizeof(kBos)}; }
Bytes ms_os_20_descriptor_set() { return {kMsOsSet.bytes, sizeof(kMsOsSet.bytes)}; }

size_t string_descriptor(uint8_t index, const char* serial, uint8_t* out, size_t capacity) {
  if (capacity < 4) return 0;
  if (index == kLanguages) {
    out[0] = 4;
    out[1] = kStringDescriptor;
    out[2] = lo(0x0409);  // English (United States)
    out[3] = hi(0x0409);
    return 4;
  }
  const char* text = nullptr;
  switch (index) {
    case kManufacturer: text = "Bench Digitizer"; break;
    case kProduct: text = "Bench digitizer controller"; break;
    case kSerial: text = serial; break;
    case kInterfaceName: text = kInterfaceNameText; break;
    default: return 0;
  }
  if (text == nullptr) return 0;
  size_t n = 2;
  // A string descriptor's length is one byte: at most 126 characters.
  for (; *text != '\0' && n + 2 <= capacity && n + 2 <= 254; ++text) {
    out[n++] = static_cast<uint8_t>(*text);
    out[n++] = 0;
  }
  out[0] = static_cast<uint8_t>(n);
  out[1] = kStringDescriptor;
  return n;
}

}  // namespace dg::usb

// The descriptors parse as a host parses them: lengths add up, the interface is vendor class with
// one bulk endpoint each way, and the MS OS 2.0 set that binds WinUSB is what the BOS announces.
#include "hw/usb/descriptors.h"

#include <string>

#include "CppUTest/TestHarness.h"

namespace {

uint16_t le16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | p[1] << 8); }

std::string from_utf16(const uint8_t* p, size_t bytes) {
  std::string out;
  for (size_t i = 0; i + 1 < bytes; i += 2) {
    CHECK_EQUAL(0, p[i + 1]);  // ASCII only
    out.push_back(static_cast<char>(p[i]));
  }
  return out;
}

}  // namespace

using namespace dg::usb;

TEST_GROUP(UsbDescriptors) {};

TEST(UsbDescriptors, DeviceDescriptorNamesTheHostsDefaultIdsAndAnnouncesBos) {
  const Bytes d = device_descriptor();
  LONGS_EQUAL(18, d.size);
  LONGS_EQUAL(18, d.data[0]);
  LONGS_EQUAL(kDeviceDescriptor, d.data[1]);
  CHECK(le16(d.data + 2) >= 0x0201);  // BOS is read only from 2.01 on
  LONGS_EQUAL(64, d.data[7]);
  LONGS_EQUAL(0x1209, le16(d.data + 8));
  LONGS_EQUAL(0x0001, le16(d.data + 10));
  LONGS_EQUAL(kSerial, d.data[16]);
  LONGS_EQUAL(1, d.data[17]);
}

TEST(UsbDescriptors, ConfigurationWalksToOneVendorInterfaceWithTwoBulkEndpoints) {
  const Bytes c = configuration_descriptor();
  LONGS_EQUAL(c.size, le16(c.data + 2));
  size_t at = 0;
  int interfaces = 0, bulk_in = 0, bulk_out = 0;
  while (at < c.size) {
    const uint8_t length = c.data[at];
    CHECK(length >= 2);
    CHECK(at + length <= c.size);
    const uint8_t* d = c.data + at;
    if (d[1] == kInterfaceDescriptor) {
      ++interfaces;
      LONGS_EQUAL(0xFF, d[5]);  // vendor specific: the host matches on it
      LONGS_EQUAL(2, d[4]);
    }
    if (d[1] == kEndpointDescriptor) {
      LONGS_EQUAL(2, d[3] & 3);  // bulk
      LONGS_EQUAL(64, le16(d + 4));
      if (d[2] & 0x80) ++bulk_in; else ++bulk_out;
    }
    at += length;
  }
  LONGS_EQUAL(c.size, at);
  LONGS_EQUAL(1, interfaces);
  LONGS_EQUAL(1, bulk_in);
  LONGS_EQUAL(1, bulk_out);
  LONGS_EQUAL(1, c.data[4]);
}

TEST(UsbDescriptors, BosAnnouncesTheMsOs20SetByItsLengthAndVendorCode) {
  const Bytes b = bos_descriptor();
  LONGS_EQUAL(b.size, le16(b.data + 2));
  LONGS_EQUAL(1, b.data[4]);
  const uint8_t* cap = b.data + 5;
  LONGS_EQUAL(28, cap[0]);
  LONGS_EQUAL(kDeviceCapabilityDescriptor, cap[1]);
  LONGS_EQUAL(5, cap[2]);  // platform
  const uint8_t uuid[16] = {0xDF, 0x60, 0xDD, 0xD8, 0x89, 0x45, 0xC7, 0x4C,
                            0x9C, 0xD2, 0x65, 0x9D, 0x9E, 0x64, 0x8A, 0x9F};
  MEMCMP_EQUAL(uuid, cap + 4, 16);
  LONGS_EQUAL(ms_os_20_descriptor_set().size, le16(cap + 24));
  LONGS_EQUAL(kMsVendorCode, cap[26]);
}

TEST(UsbDescriptors, MsOs20SetBindsWinUsbAndNamesAnInterfaceGuid) {
  const Bytes s = ms_os_20_descriptor_set();
  LONGS_EQUAL(10, le16(s.data));
  LONGS_EQUAL(0, le16(s.data + 2));
  LONGS_EQUAL(s.size, le16(s.data + 8));
  size_t at = 10;
  bool compatible = false, property = false;
  while (at < s.size) {
    const uint8_t* d = s.data + at;
    const uint16_t length = le16(d);
    CHECK(length >= 4 && at + length <= s.size);
    if (le16(d + 2) == 3) {
      compatible = true;
      LONGS_EQUAL(20, length);
      MEMCMP_EQUAL("WINUSB\0\0", d + 4, 8);
    }
    if (le16(d + 2) == 4) {
      property = true;
      LONGS_EQUAL(7, le16(d + 4));  // REG_MULTI_SZ
      const uint16_t name_length = le16(d + 6);
      CHECK(std::string("DeviceInterfaceGUIDs") + '\0' == from_utf16(d + 8, name_length));
      LONGS_EQUAL(42, name_length);
      const uint16_t data_length = le16(d + 8 + name_length);
      LONGS_EQUAL(length, 10 + name_length + data_length);
      const std::string guids = from_utf16(d + 10 + name_length, data_length);
      LONGS_EQUAL(40, guids.size());  // one GUID and the two terminators of a multi-string
      CHECK_EQUAL('{', guids[0]);
      CHECK_EQUAL('}', guids[37]);
      CHECK_EQUAL('\0', guids[38]);
      CHECK_EQUAL('\0', guids[39]);
      for (size_t dash : {9u, 14u, 19u, 24u}) CHECK_EQUAL('-', guids[dash]);
    }
    at += length;
  }
  LONGS_EQUAL(s.size, at);
  CHECK(compatible);
  CHECK(property);
}

TEST(UsbDescriptors, StringsAreUtf16WithTheirLengthAndUnknownIndexesAreAbsent) {
  uint8_t out[256];
  LONGS_EQUAL(4, string_descriptor(kLanguages, "X", out, sizeof(out)));
  LONGS_EQUAL(0x0409, le16(out + 2));
  const size_t n = string_descriptor(kSerial, "0123456789AB", out, sizeof(out));
  LONGS_EQUAL(2 + 24, n);
  LONGS_EQUAL(n, out[0]);
  LONGS_EQUAL(kStringDescriptor, out[1]);
  STRCMP_EQUAL("0123456789AB", from_utf16(out + 2, n - 2).c_str());
  LONGS_EQUAL(0, string_descriptor(9, "X", out, sizeof(out)));
  LONGS_EQUAL(0, string_descriptor(kSerial, nullptr, out, sizeof(out)));
  // A short buffer cuts the text; the length byte says what was written.
  LONGS_EQUAL(8, string_descriptor(kProduct, "X", out, 9));
  LONGS_EQUAL(8, out[0]);
}

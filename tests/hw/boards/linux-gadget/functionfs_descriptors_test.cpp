// The FunctionFS blobs are what the kernel's parser (drivers/usb/gadget/function/f_fs.c) expects:
// v2 header, counts that match the descriptors, lengths that add up; and the interface and
// endpoints are the STM32 board's, so the host sees one device whichever board it meets.
#include "hw/boards/linux-gadget/functionfs_descriptors.h"

#include <linux/usb/functionfs.h>

#include <string>

#include "CppUTest/TestHarness.h"
#include "hw/usb/descriptors.h"

namespace {

uint32_t le32(const std::vector<uint8_t>& b, size_t at) {
  return uint32_t{b[at]} | uint32_t{b[at + 1]} << 8 | uint32_t{b[at + 2]} << 16 | uint32_t{b[at + 3]} << 24;
}

}  // namespace

TEST_GROUP(FunctionFsDescriptors) {};

TEST(FunctionFsDescriptors, HeaderCountsAndLengthsMatchTheDescriptors) {
  const std::vector<uint8_t> blob = dg::gadget::functionfs_descriptors();
  LONGS_EQUAL(FUNCTIONFS_DESCRIPTORS_MAGIC_V2, le32(blob, 0));
  LONGS_EQUAL(blob.size(), le32(blob, 4));
  LONGS_EQUAL(FUNCTIONFS_HAS_FS_DESC | FUNCTIONFS_HAS_HS_DESC | FUNCTIONFS_HAS_MS_OS_DESC, le32(blob, 8));
  const uint32_t fs_count = le32(blob, 12), hs_count = le32(blob, 16), os_count = le32(blob, 20);
  LONGS_EQUAL(3, fs_count);
  LONGS_EQUAL(3, hs_count);
  LONGS_EQUAL(1, os_count);
  size_t at = 24, seen = 0;
  while (seen < fs_count + hs_count) {
    CHECK(at < blob.size() && blob[at] >= 2);
    at += blob[at];
    ++seen;
  }
  // The OS descriptor closes the blob, and its own length says where it ends.
  LONGS_EQUAL(blob.size(), at + le32(blob, at + 1));
}

TEST(FunctionFsDescriptors, TheInterfaceIsCompatibleWithWinUsbForWindows) {
  const std::vector<uint8_t> blob = dg::gadget::functionfs_descriptors();
  const size_t os = blob.size() - 35;  // an 11-byte header and one 24-byte function section
  LONGS_EQUAL(dg::usb::kInterfaceNumber, blob[os]);
  LONGS_EQUAL(35, le32(blob, os + 1));
  LONGS_EQUAL(1, blob[os + 5] | blob[os + 6] << 8);  // what FunctionFS accepts up to Linux 6.1
  LONGS_EQUAL(4, blob[os + 7] | blob[os + 8] << 8);        // extended compat ID
  LONGS_EQUAL(1, blob[os + 9]);   // one function section
  LONGS_EQUAL(0, blob[os + 11]);  // for the first (only) interface
  LONGS_EQUAL(1, blob[os + 12]);  // Reserved1
  STRCMP_EQUAL("WINUSB", std::string(reinterpret_cast<const char*>(blob.data() + os + 13), 6).c_str());
  for (size_t i = os + 19; i < blob.size(); ++i) LONGS_EQUAL(0, blob[i]);  // padding, sub-ID, Reserved2
}

TEST(FunctionFsDescriptors, FullSpeedSetIsTheStm32BoardsInterfaceAndHighSpeedUses512BytePackets) {
  const std::vector<uint8_t> blob = dg::gadget::functionfs_descriptors();
  const dg::usb::Bytes config = dg::usb::configuration_descriptor();
  const size_t set_size = config.size - 9u;
  std::vector<uint8_t> expected(config.data + 9, config.data + config.size);
  expected[8] = 1;  // FunctionFS numbers the interface's string itself
  const std::vector<uint8_t> full(blob.begin() + 24, blob.begin() + 24 + static_cast<long>(set_size));
  CHECK(expected == full);
  const uint8_t* high = blob.data() + 24 + set_size;
  LONGS_EQUAL(0xFF, high[5]);  // vendor class
  for (size_t ep : {9u, 16u}) {
    LONGS_EQUAL(dg::usb::kEndpointDescriptor, high[ep + 1]);
    LONGS_EQUAL(2, high[ep + 3]);  // bulk
    LONGS_EQUAL(512, high[ep + 4] | high[ep + 5] << 8);
  }
  LONGS_EQUAL(dg::usb::kBulkOutEndpoint, high[9 + 2]);
  LONGS_EQUAL(dg::usb::kBulkInEndpoint, high[16 + 2]);
}

TEST(FunctionFsDescriptors, StringsBlobHoldsOneEnglishStringWithItsTerminator) {
  const std::vector<uint8_t> blob = dg::gadget::functionfs_strings();
  LONGS_EQUAL(FUNCTIONFS_STRINGS_MAGIC, le32(blob, 0));
  LONGS_EQUAL(blob.size(), le32(blob, 4));
  LONGS_EQUAL(1, le32(blob, 8));
  LONGS_EQUAL(1, le32(blob, 12));
  LONGS_EQUAL(0x0409, blob[16] | blob[17] << 8);
  CHECK_EQUAL('\0', static_cast<char>(blob.back()));
  STRCMP_EQUAL("digitizer link", reinterpret_cast<const char*>(blob.data() + 18));
}

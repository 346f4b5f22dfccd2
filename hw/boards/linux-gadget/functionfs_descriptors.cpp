// The interface and endpoint descriptors are taken from hw/usb's configuration descriptor, so the
// two boards cannot drift apart; only what FunctionFS numbers itself is changed: the interface's
// string index (FunctionFS counts its own strings from 1) and, at high speed, the bulk packet size
// (512 bytes, the only one high speed allows).
#include "hw/boards/linux-gadget/functionfs_descriptors.h"

#include <linux/usb/functionfs.h>

#include "hw/usb/descriptors.h"

namespace dg::gadget {

namespace {

void put32(std::vector<uint8_t>& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
}

// The interface and endpoint descriptors of the configuration, after its 9-byte header.
std::vector<uint8_t> interface_descriptors(uint16_t bulk_packet_size) {
  const usb::Bytes config = usb::configuration_descriptor();
  std::vector<uint8_t> out(config.data + 9, config.data + config.size);
  for (size_t at = 0; at < out.size(); at += out[at]) {
    if (out[at + 1] == usb::kInterfaceDescriptor) out[at + 8] = 1;  // iInterface: FunctionFS string 1
    if (out[at + 1] == usb::kEndpointDescriptor) {
      out[at + 4] = static_cast<uint8_t>(bulk_packet_size & 0xFF);
      out[at + 5] = static_cast<uint8_t>(bulk_packet_size >> 8);
    }
  }
  return out;
}

size_t count_descriptors(const std::vector<uint8_t>& bytes) {
  size_t n = 0;
  for (size_t at = 0; at < bytes.size(); at += bytes[at]) ++n;
  return n;
}

void patch_length(std::vector<uint8_t>& out) {
  const uint32_t length = static_cast<uint32_t>(out.size());
  for (int i = 0; i < 4; ++i) out[4 + i] = static_cast<uint8_t>(length >> (8 * i));
}

// Microsoft OS 1.0 extended compat ID descriptor for the interface: compatible ID "WINUSB", so
// Windows binds WinUSB without a driver install (FunctionFS cannot carry the BOS descriptor and
// MS OS 2.0 set the STM32 board uses; it serves these through the composite framework's 0xEE
// string and vendor request). Layout: struct usb_os_desc_header and usb_ext_compat_desc.
std::vector<uint8_t> winusb_compat_id() {
  std::vector<uint8_t> out;
  out.push_back(usb::kInterfaceNumber);  // interface
  put32(out, 11 + 24);                   // dwLength: this 11-byte header and one function section
  // bcdVersion: 1.00 would be 0x0100, but FunctionFS up to Linux 6.1 accepts only the value 1
  // (later kernels take both), and the host never sees this field: the kernel writes its own.
  out.push_back(0x01);
  out.push_back(0x00);
  out.push_back(0x04);                   // wIndex 4: extended compat ID
  out.push_back(0x00);
  out.push_back(1);                      // bCount
  out.push_back(0);                      // reserved
  out.push_back(usb::kInterfaceNumber);  // bFirstInterfaceNumber
  out.push_back(1);                      // Reserved1 (1, as the specification says)
  const char compatible[8] = {'W', 'I', 'N', 'U', 'S', 'B', 0, 0};
  out.insert(out.end(), compatible, compatible + 8);
  out.insert(out.end(), 8 + 6, 0);  // SubCompatibleID, Reserved2
  return out;
}

}  // namespace

std::vector<uint8_t> functionfs_descriptors() {
  const std::vector<uint8_t> full = interface_descriptors(usb::kBulkPacketSize);
  const std::vector<uint8_t> high = interface_descriptors(512);
  const std::vector<uint8_t> os = winusb_compat_id();
  std::vector<uint8_t> out;
  put32(out, FUNCTIONFS_DESCRIPTORS_MAGIC_V2);
  put32(out, 0);  // length, patched below
  put32(out, FUNCTIONFS_HAS_FS_DESC | FUNCTIONFS_HAS_HS_DESC | FUNCTIONFS_HAS_MS_OS_DESC);
  put32(out, static_cast<uint32_t>(count_descriptors(full)));
  put32(out, static_cast<uint32_t>(count_descriptors(high)));
  put32(out, 1);  // MS OS descriptors
  out.insert(out.end(), full.begin(), full.end());
  out.insert(out.end(), high.begin(), high.end());
  out.insert(out.end(), os.begin(), os.end());
  patch_length(out);
  return out;
}

std::vector<uint8_t> functionfs_strings() {
  std::vector<uint8_t> out;
  put32(out, FUNCTIONFS_STRINGS_MAGIC);
  put32(out, 0);
  put32(out, 1);  // strings
  put32(out, 1);  // languages
  out.push_back(0x09);  // 0x0409, English (United States)
  out.push_back(0x04);
  out.insert(out.end(), usb::kInterfaceNameText, usb::kInterfaceNameText + sizeof(usb::kInterfaceNameText));  // with its NUL
  patch_length(out);
  return out;
}

}  // namespace dg::gadget

// system-msos: asks a controller on the bus what Windows asks before it picks a driver (the
// Microsoft OS 1.0 string descriptor 0xEE, then the extended compat ID through the vendor request
// the string names), and prints the compatible ID. For the system tests' Linux-gadget check.
//   system-msos SERIAL
#include <libusb.h>

#include <cstdio>
#include <cstring>
#include <string>

namespace {

int fail(const char* what, int status) {
  std::printf("msos: %s: %s\n", what, libusb_error_name(status));
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: system-msos SERIAL\n");
    return 2;
  }
  libusb_context* context = nullptr;
  if (libusb_init(&context) != 0) return 1;
  libusb_device** devices = nullptr;
  const ssize_t count = libusb_get_device_list(context, &devices);
  libusb_device_handle* handle = nullptr;
  for (ssize_t i = 0; i < count && handle == nullptr; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(devices[i], &d) != 0 || d.idVendor != 0x1209 || d.idProduct != 0x0001) continue;
    if (libusb_open(devices[i], &handle) != 0) continue;
    unsigned char serial[64] = {};
    if (libusb_get_string_descriptor_ascii(handle, d.iSerialNumber, serial, sizeof serial) < 0 ||
        std::strcmp(reinterpret_cast<char*>(serial), argv[1]) != 0) {
      libusb_close(handle);
      handle = nullptr;
    }
  }
  libusb_free_device_list(devices, 1);
  if (handle == nullptr) {
    std::printf("msos: no device 1209:0001 with serial %s\n", argv[1]);
    return 1;
  }
  unsigned char string[64] = {};
  int got = libusb_get_string_descriptor(handle, 0xEE, 0, string, sizeof string);
  if (got < 0) return fail("string 0xEE", got);
  // bLength 18, type 3, "MSFT100" in UTF-16LE, then the vendor code.
  std::string signature;
  for (int at = 2; at < 16 && at < got; at += 2) signature.push_back(static_cast<char>(string[at]));
  if (got < 18 || signature != "MSFT100") {
    std::printf("msos: string 0xEE is not an MS OS 1.0 descriptor\n");
    return 1;
  }
  const uint8_t vendor_code = string[16];
  unsigned char compat[40] = {};
  got = libusb_control_transfer(handle, LIBUSB_ENDPOINT_IN | LIBUSB_REQUEST_TYPE_VENDOR | LIBUSB_RECIPIENT_DEVICE,
                                vendor_code, 0, 4, compat, sizeof compat, 1000);
  if (got < 0) return fail("extended compat ID request", got);
  // A 16-byte header (dwLength @0, bcdVersion @4, wIndex 4 @6, bCount @8), then 24 bytes a function.
  if (got < 40 || compat[6] != 4 || compat[8] < 1) {
    std::printf("msos: the extended compat ID descriptor is short or malformed (%d bytes)\n", got);
    return 1;
  }
  std::printf("msos: vendor code 0x%02x, interface %u compatible id %.8s\n", vendor_code, compat[16],
              reinterpret_cast<char*>(compat + 18));
  libusb_close(handle);
  libusb_exit(context);
  return 0;
}

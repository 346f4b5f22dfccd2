// usb: the device over USB through libusb-1.0: a vendor-specific interface with one bulk IN and
// one bulk OUT endpoint, found by VID:PID and serial number; reads are asynchronous transfers
// kept in flight, and hotplug events notice a device that leaves or comes back.
#pragma once
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include <libusb.h>

#include "host/transport/transport.h"

namespace dg::host {

// pid.codes' test IDs (VID 0x1209 lends PIDs below 0x1000 for tests); a build or a user with an
// assigned ID sets DIGITIZER_USB_ID=VVVV:PPPP or names it in the URI.
constexpr uint16_t kDefaultUsbVendor = 0x1209;
constexpr uint16_t kDefaultUsbProduct = 0x0001;

struct UsbSelector {
  uint16_t vendor = kDefaultUsbVendor;
  uint16_t product = kDefaultUsbProduct;
  std::string serial;  // empty: the first matching device
};

// Parses "usb:", "usb:VVVV:PPPP", "usb:serial=S" or "usb:VVVV:PPPP,serial=S" (hex IDs); the
// default IDs come from $DIGITIZER_USB_ID when set. Throws std::invalid_argument naming the fault.
UsbSelector parse_usb_uri(const std::string& uri);

struct UsbDeviceInfo {
  uint16_t vendor = 0, product = 0;
  uint8_t bus = 0, address = 0;
  std::string serial, product_name;
  std::string problem;  // why it cannot be opened (permissions), empty when it can
};

// The matching devices on the bus (for `digitizer devices`). Throws TransportError when libusb
// cannot start (no USB on this machine).
std::vector<UsbDeviceInfo> list_usb_devices(const UsbSelector& selector);

// "libusb 1.0.26.11724": the USB library and its version, for `digitizer doctor`.
std::string usb_library_version();

class UsbTransport final : public Transport {
 public:
  // Opens the first device that matches; TransportError names what was looked for and why none
  // could be opened.
  explicit UsbTransport(const std::string& uri);
  ~UsbTransport() override;
  UsbTransport(const UsbTransport&) = delete;
  UsbTransport& operator=(const UsbTransport&) = delete;

  void write(const uint8_t* data, size_t size) override;
  size_t read(uint8_t* data, size_t capacity, int timeout_ms) override;
  std::string describe() const override { return uri_; }
  bool reconnectable() const override { return true; }
  void reconnect() override;
  void disconnect() override;

 private:
  static void LIBUSB_CALL on_transfer(libusb_transfer* transfer);
  static int LIBUSB_CALL on_hotplug(libusb_context* context, libusb_device* device, libusb_hotplug_event event, void* self);
  void start_context();
  void stop_context();
  void open_device();
  void close_device();
  void check_present() const;

  std::string uri_;
  UsbSelector selector_;
  libusb_context* context_ = nullptr;
  libusb_device_handle* handle_ = nullptr;
  libusb_device* device_ = nullptr;  // the opened device, for hotplug's "left" event
  int interface_ = -1;
  uint8_t endpoint_in_ = 0, endpoint_out_ = 0;
  uint16_t packet_in_ = 64;
  libusb_hotplug_callback_handle hotplug_handle_ = 0;
  bool gone_ = false;  // unplugged (hotplug or a transfer that found no device)
  std::string gone_reason_;
  // Bulk IN transfers kept submitted so the device never waits for the host to ask.
  std::vector<libusb_transfer*> transfers_;
  std::vector<std::vector<uint8_t>> buffers_;
  int in_flight_ = 0;
  std::deque<uint8_t> received_;
};

}  // namespace dg::host

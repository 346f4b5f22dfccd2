// libusb-1.0 transport: asynchronous bulk IN, synchronous bulk OUT with a time limit, hotplug.
#include "host/transport/usb_transport.h"

#include <libusb.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace dg::host {

namespace {

constexpr int kTransfersInFlight = 4;
constexpr int kTransferBytes = 4096;
constexpr unsigned kWriteTimeoutMs = 2000;

std::string usb_error(int code) { return libusb_strerror(static_cast<libusb_error>(code)); }

bool parse_hex16(const std::string& text, uint16_t* out) {
  if (text.empty() || text.size() > 4) return false;
  char* end = nullptr;
  const unsigned long v = std::strtoul(text.c_str(), &end, 16);
  if (*end != '\0') return false;
  *out = static_cast<uint16_t>(v);
  return true;
}

bool parse_ids(const std::string& text, UsbSelector* s) {
  const size_t colon = text.find(':');
  return colon != std::string::npos && parse_hex16(text.substr(0, colon), &s->vendor) &&
         parse_hex16(text.substr(colon + 1), &s->product);
}

std::string ids_text(const UsbSelector& s) {
  char text[16];
  std::snprintf(text, sizeof text, "%04x:%04x", s.vendor, s.product);
  return text;
}

std::string string_descriptor(libusb_device_handle* handle, uint8_t index) {
  if (index == 0) return "";
  unsigned char text[128] = {};
  const int n = libusb_get_string_descriptor_ascii(handle, index, text, sizeof(text));
  return n > 0 ? std::string(reinterpret_cast<char*>(text), static_cast<size_t>(n)) : "";
}

// The vendor-specific interface's bulk endpoints; false when the device has none.
bool find_bulk_interface(libusb_device* device, int* interface, uint8_t* in, uint8_t* out, uint16_t* packet_in) {
  libusb_config_descriptor* config = nullptr;
  if (libusb_get_active_config_descriptor(device, &config) != 0) return false;
  bool found = false;
  for (int i = 0; i < config->bNumInterfaces && !found; ++i) {
    const libusb_interface& alternatives = config->interface[i];
    if (alternatives.num_altsetting < 1) continue;
    const libusb_interface_descriptor& d = alternatives.altsetting[0];
    if (d.bInterfaceClass != LIBUSB_CLASS_VENDOR_SPEC) continue;
    uint8_t bulk_in = 0, bulk_out = 0;
    uint16_t size = 64;
    for (int e = 0; e < d.bNumEndpoints; ++e) {
      const libusb_endpoint_descriptor& ep = d.endpoint[e];
      if ((ep.bmAttributes & LIBUSB_TRANSFER_TYPE_MASK) != LIBUSB_TRANSFER_TYPE_BULK) continue;
      if (ep.bEndpointAddress & LIBUSB_ENDPOINT_IN) {
        bulk_in = ep.bEndpointAddress;
        size = ep.wMaxPacketSize;
      } else {
        bulk_out = ep.bEndpointAddress;
      }
    }
    if (bulk_in != 0 && bulk_out != 0) {
      *interface = d.bInterfaceNumber;
      *in = bulk_in;
      *out = bulk_out;
      *packet_in = size;
      found = true;
    }
  }
  libusb_free_config_descriptor(config);
  return found;
}

struct Context {
  Context() {
    const int status = libusb_init(&context);
    if (status != 0) throw TransportError("usb: cannot start libusb: " + usb_error(status));
  }
  ~Context() { libusb_exit(context); }
  libusb_context* context = nullptr;
};

}  // namespace

std::string usb_library_version() {
  const libusb_version* v = libusb_get_version();
  return "libusb " + std::to_string(v->major) + "." + std::to_string(v->minor) + "." + std::to_string(v->micro) + "." +
         std::to_string(v->nano);
}

UsbSelector parse_usb_uri(const std::string& uri) {
  UsbSelector s;
  if (const char* env = std::getenv("DIGITIZER_USB_ID"); env != nullptr && *env != '\0') {
    if (!parse_ids(env, &s)) throw std::invalid_argument(std::string("DIGITIZER_USB_ID='") + env + "' is not VVVV:PPPP in hex");
  }
  if (uri.rfind("usb:", 0) != 0) throw std::invalid_argument("device URI '" + uri + "' is not a usb: URI");
  std::string rest = uri.substr(4);
  const size_t serial_at = rest.find("serial=");
  if (serial_at != std::string::npos) {
    s.serial = rest.substr(serial_at + 7);
    if (s.serial.empty()) throw std::invalid_argument("device URI '" + uri + "': serial= needs a serial number");
    rest = rest.substr(0, serial_at);
    if (!rest.empty() && rest.back() == ',') rest.pop_back();
  }
  if (!rest.empty() && !parse_ids(rest, &s)) {
    throw std::invalid_argument("device URI '" + uri + "': expected usb:VVVV:PPPP[,serial=S] with hex IDs");
  }
  return s;
}

std::vector<UsbDeviceInfo> list_usb_devices(const UsbSelector& selector) {
  Context usb;
  libusb_device** devices = nullptr;
  const ssize_t count = libusb_get_device_list(usb.context, &devices);
  if (count < 0) throw TransportError("usb: cannot list devices: " + usb_error(static_cast<int>(count)));
  std::vector<UsbDeviceInfo> found;
  for (ssize_t i = 0; i < count; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(devices[i], &d) != 0) continue;
    if (d.idVendor != selector.vendor || d.idProduct != selector.product) continue;
    UsbDeviceInfo info;
    info.vendor = d.idVendor;
    info.product = d.idProduct;
    info.bus = libusb_get_bus_number(devices[i]);
    info.address = libusb_get_device_address(devices[i]);
    libusb_device_handle* handle = nullptr;
    const int status = libusb_open(devices[i], &handle);
    if (status == 0) {
      info.serial = string_descriptor(handle, d.iSerialNumber);
      info.product_name = string_descriptor(handle, d.iProduct);
      libusb_close(handle);
    } else {
      info.problem = status == LIBUSB_ERROR_ACCESS ? "no permission (install the udev rule: scripts/install-udev-rule)"
                                                   : usb_error(status);
    }
    if (!selector.serial.empty() && info.problem.empty() && info.serial != selector.serial) continue;
    found.push_back(info);
  }
  libusb_free_device_list(devices, 1);
  return found;
}

UsbTransport::UsbTransport(const std::string& uri) : uri_(uri), selector_(parse_usb_uri(uri)) {
  if (uri_ == "usb:") uri_ += ids_text(selector_);  // messages say which IDs were looked for
  start_context();
  try {
    open_device();
  } catch (...) {
    stop_context();
    throw;
  }
}

UsbTransport::~UsbTransport() {
  close_device();
  stop_context();
}

void UsbTransport::start_context() {
  const int status = libusb_init(&context_);
  if (status != 0) throw TransportError(uri_ + ": cannot start libusb: " + usb_error(status));
  if (libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG)) {
    libusb_hotplug_register_callback(context_,
                                     static_cast<libusb_hotplug_event>(LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED |
                                                                       LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT),
                                     LIBUSB_HOTPLUG_NO_FLAGS, selector_.vendor, selector_.product,
                                     LIBUSB_HOTPLUG_MATCH_ANY, &UsbTransport::on_hotplug, this, &hotplug_handle_);
  }
}

void UsbTransport::stop_context() {
  if (context_ == nullptr) return;
  if (hotplug_handle_ != 0) libusb_hotplug_deregister_callback(context_, hotplug_handle_);
  hotplug_handle_ = 0;
  libusb_exit(context_);
  context_ = nullptr;
}

int LIBUSB_CALL UsbTransport::on_hotplug(libusb_context*, libusb_device* device, libusb_hotplug_event event, void* self) {
  auto* transport = static_cast<UsbTransport*>(self);
  if (event == LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT && device == transport->device_) {
    transport->gone_ = true;
    transport->gone_reason_ = "the device was unplugged";
  }
  return 0;  // stay registered
}

void UsbTransport::open_device() {
  libusb_device** devices = nullptr;
  const ssize_t count = libusb_get_device_list(context_, &devices);
  if (count < 0) throw TransportError(uri_ + ": cannot list USB devices: " + usb_error(static_cast<int>(count)));
  std::string problem;
  for (ssize_t i = 0; i < count && handle_ == nullptr; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(devices[i], &d) != 0) continue;
    if (d.idVendor != selector_.vendor || d.idProduct != selector_.product) continue;
    libusb_device_handle* handle = nullptr;
    const int status = libusb_open(devices[i], &handle);
    if (status != 0) {
      problem = status == LIBUSB_ERROR_ACCESS ? "permission denied (install the udev rule: scripts/install-udev-rule)"
                                              : usb_error(status);
      continue;
    }
    if (!selector_.serial.empty() && string_descriptor(handle, d.iSerialNumber) != selector_.serial) {
      libusb_close(handle);
      continue;
    }
    if (!find_bulk_interface(devices[i], &interface_, &endpoint_in_, &endpoint_out_, &packet_in_)) {
      problem = "it has no vendor-specific interface with bulk endpoints (not our firmware?)";
      libusb_close(handle);
      continue;
    }
    libusb_set_auto_detach_kernel_driver(handle, 1);
    const int claimed = libusb_claim_interface(handle, interface_);
    if (claimed != 0) {
      problem = "cannot claim its interface: " + usb_error(claimed) + (claimed == LIBUSB_ERROR_BUSY ? " (another program has it)" : "");
      libusb_close(handle);
      continue;
    }
    handle_ = handle;
    device_ = libusb_ref_device(devices[i]);
  }
  libusb_free_device_list(devices, 1);
  if (handle_ == nullptr) {
    throw TransportError(uri_ + ": no usable device " + ids_text(selector_) +
                         (selector_.serial.empty() ? "" : " with serial " + selector_.serial) +
                         (problem.empty() ? " is connected" : ": " + problem));
  }
  gone_ = false;
  received_.clear();
  buffers_.assign(kTransfersInFlight, std::vector<uint8_t>(kTransferBytes));
  for (int i = 0; i < kTransfersInFlight; ++i) {
    libusb_transfer* transfer = libusb_alloc_transfer(0);
    libusb_fill_bulk_transfer(transfer, handle_, endpoint_in_, buffers_[static_cast<size_t>(i)].data(), kTransferBytes,
                              &UsbTransport::on_transfer, this, 0);
    transfers_.push_back(transfer);
    if (libusb_submit_transfer(transfer) == 0) ++in_flight_;
  }
}

void LIBUSB_CALL UsbTransport::on_transfer(libusb_transfer* transfer) {
  auto* self = static_cast<UsbTransport*>(transfer->user_data);
  --self->in_flight_;
  switch (transfer->status) {
    case LIBUSB_TRANSFER_COMPLETED:
      self->received_.insert(self->received_.end(), transfer->buffer, transfer->buffer + transfer->actual_length);
      break;
    case LIBUSB_TRANSFER_CANCELLED:
      return;  // closing
    case LIBUSB_TRANSFER_NO_DEVICE:
      self->gone_ = true;
      self->gone_reason_ = "the device was unplugged";
      return;
    case LIBUSB_TRANSFER_STALL:
      libusb_clear_halt(transfer->dev_handle, transfer->endpoint);
      break;
    default:  // a transmission error: the link layer repairs the lost bytes
      break;
  }
  if (!self->gone_ && libusb_submit_transfer(transfer) == 0) ++self->in_flight_;
}

void UsbTransport::check_present() const {
  if (handle_ == nullptr) throw TransportError(uri_ + ": not connected");
  if (gone_) throw TransportError(uri_ + ": " + gone_reason_);
}

void UsbTransport::write(const uint8_t* data, size_t size) {
  check_present();
  size_t done = 0;
  while (done < size) {
    int sent = 0;
    const int status = libusb_bulk_transfer(handle_, endpoint_out_, const_cast<uint8_t*>(data + done),
                                            static_cast<int>(size - done), &sent, kWriteTimeoutMs);
    done += static_cast<size_t>(sent);
    if (status == LIBUSB_ERROR_NO_DEVICE) {
      gone_ = true;
      gone_reason_ = "the device was unplugged";
    }
    if (status == LIBUSB_ERROR_PIPE) libusb_clear_halt(handle_, endpoint_out_);
    if (status != 0 && status != LIBUSB_ERROR_PIPE) {
      check_present();
      throw TransportError(uri_ + ": write failed: " + usb_error(status));
    }
  }
}

size_t UsbTransport::read(uint8_t* data, size_t capacity, int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    check_present();
    if (!received_.empty()) {
      size_t n = 0;
      while (n < capacity && !received_.empty()) {
        data[n++] = received_.front();
        received_.pop_front();
      }
      return n;
    }
    const auto left = std::chrono::duration_cast<std::chrono::microseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return 0;
    timeval tv{static_cast<time_t>(left.count() / 1000000), static_cast<suseconds_t>(left.count() % 1000000)};
    const int status = libusb_handle_events_timeout_completed(context_, &tv, nullptr);
    if (status != 0 && status != LIBUSB_ERROR_INTERRUPTED) throw TransportError(uri_ + ": " + usb_error(status));
    if (in_flight_ == 0 && !gone_) {
      gone_ = true;
      gone_reason_ = "no read transfer is left (the device stopped answering)";
    }
  }
}

void UsbTransport::close_device() {
  if (handle_ == nullptr) return;
  for (libusb_transfer* t : transfers_) libusb_cancel_transfer(t);
  // Cancelled transfers must complete before they are freed.
  for (int rounds = 0; in_flight_ > 0 && rounds < 100; ++rounds) {
    timeval tv{0, 10000};
    libusb_handle_events_timeout_completed(context_, &tv, nullptr);
  }
  for (libusb_transfer* t : transfers_) libusb_free_transfer(t);
  transfers_.clear();
  in_flight_ = 0;
  libusb_release_interface(handle_, interface_);
  libusb_close(handle_);
  handle_ = nullptr;
  if (device_ != nullptr) libusb_unref_device(device_);
  device_ = nullptr;
}

void UsbTransport::disconnect() { close_device(); }

void UsbTransport::reconnect() {
  close_device();
  // A fresh context enumerates the bus again. Debian's libusb learns of devices that come and go
  // from udevd's announcements; on a host without udevd (a container, a minimal system) the old
  // context would never see the device come back.
  stop_context();
  start_context();
  open_device();
}

}  // namespace dg::host

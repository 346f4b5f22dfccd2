// The USB gadget the Linux-gadget board presents, made through configfs: the device's IDs and
// strings from hw/usb (so the host sees the same device as the STM32 board), one configuration with
// one FunctionFS function, its instance mounted where FunctionFsLink opens it, and the binding to
// a UDC. Torn down again when the object goes.
#pragma once
#include <string>
#include <vector>

namespace dg::gadget {

struct GadgetSettings {
  std::string configfs = "/sys/kernel/config";
  std::string name = "digitizer";      // the gadget's directory under usb_gadget/
  std::string mount_dir = "/dev/ffs-digitizer";
  std::string serial;                  // the USB serial number (usb:serial=...)
  std::string udc;                     // empty: the first in /sys/class/udc
};

class ConfigfsGadget {
 public:
  ConfigfsGadget() = default;
  ~ConfigfsGadget();
  ConfigfsGadget(const ConfigfsGadget&) = delete;
  ConfigfsGadget& operator=(const ConfigfsGadget&) = delete;

  // Creates the gadget and mounts its FunctionFS instance; false with the reason.
  bool create(const GadgetSettings& settings, std::string* error);
  // Binds to the UDC once the function has written its descriptors; false with the reason.
  bool bind(std::string* error);
  const std::string& udc() const { return udc_; }

 private:
  bool write_attribute(const std::string& path, const std::string& value, std::string* error);
  bool make_dir(const std::string& path, std::string* error);

  GadgetSettings settings_;
  std::string root_;
  std::string udc_;
  std::vector<std::string> made_;  // directories and links made, removed in reverse
  bool mounted_ = false;
  bool bound_ = false;
};

// The first UDC the kernel offers, or "" when there is none.
std::string first_udc();

}  // namespace dg::gadget

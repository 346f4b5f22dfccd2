// configfs layout: Documentation/usb/gadget_configfs.rst; FunctionFS: Documentation/usb/functionfs.rst.
#include "hw/boards/linux-gadget/configfs_gadget.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "hw/usb/descriptors.h"

namespace dg::gadget {

namespace {

// configfs takes IDs and codes as hex text, "0x1209".
std::string hex(unsigned value, int digits) {
  char text[12];
  std::snprintf(text, sizeof text, "0x%0*x", digits, value);
  return text;
}

// hw/usb's string descriptor as ASCII (its strings are ASCII).
std::string usb_string(uint8_t index) {
  uint8_t descriptor[128];
  const size_t length = usb::string_descriptor(index, "", descriptor, sizeof descriptor);
  std::string text;
  for (size_t at = 2; at + 1 < length; at += 2) text.push_back(static_cast<char>(descriptor[at]));
  return text;
}

}  // namespace

std::string first_udc() {
  std::string found;
  if (DIR* dir = opendir("/sys/class/udc")) {
    while (dirent* entry = readdir(dir)) {
      if (entry->d_name[0] != '.' && (found.empty() || found > entry->d_name)) found = entry->d_name;
    }
    closedir(dir);
  }
  return found;
}

bool ConfigfsGadget::write_attribute(const std::string& path, const std::string& value, std::string* error) {
  const int fd = open(path.c_str(), O_WRONLY | O_CLOEXEC);
  const bool ok = fd >= 0 && ::write(fd, value.data(), value.size()) == static_cast<ssize_t>(value.size());
  const int saved = errno;
  if (fd >= 0) close(fd);
  if (!ok) *error = path + ": cannot write '" + value + "': " + std::strerror(saved);
  return ok;
}

bool ConfigfsGadget::make_dir(const std::string& path, std::string* error) {
  if (mkdir(path.c_str(), 0755) != 0 && errno != EEXIST) {
    *error = path + ": " + std::strerror(errno);
    return false;
  }
  made_.push_back(path);
  return true;
}

bool ConfigfsGadget::create(const GadgetSettings& settings, std::string* error) {
  settings_ = settings;
  const std::string gadgets = settings.configfs + "/usb_gadget";
  struct stat info {};
  if (stat(gadgets.c_str(), &info) != 0) {
    *error = gadgets + ": missing (mount configfs at " + settings.configfs + " and load libcomposite)";
    return false;
  }
  root_ = gadgets + "/" + settings.name;
  const std::string strings = root_ + "/strings/0x409";
  const std::string config = root_ + "/configs/c.1";
  const std::string function = root_ + "/functions/ffs." + settings.name;
  if (!make_dir(root_, error) || !make_dir(strings, error) || !make_dir(config, error) ||
      !make_dir(config + "/strings/0x409", error) || !make_dir(function, error)) {
    return false;
  }
  if (!write_attribute(root_ + "/idVendor", hex(usb::kVendorId, 4), error) ||
      !write_attribute(root_ + "/idProduct", hex(usb::kProductId, 4), error) ||
      !write_attribute(root_ + "/bcdDevice", hex(usb::kDeviceRelease, 4), error) ||
      !write_attribute(strings + "/manufacturer", usb_string(usb::kManufacturer), error) ||
      !write_attribute(strings + "/product", usb_string(usb::kProduct), error) ||
      !write_attribute(strings + "/serialnumber", settings.serial, error) ||
      !write_attribute(config + "/strings/0x409/configuration", usb_string(usb::kInterfaceName), error)) {
    return false;
  }
  const std::string link = config + "/ffs." + settings.name;
  if (symlink(function.c_str(), link.c_str()) != 0 && errno != EEXIST) {
    *error = link + ": " + std::strerror(errno);
    return false;
  }
  made_.push_back(link);
  // Microsoft OS 1.0 descriptors (string 0xEE and its vendor request) for the configuration, so
  // Windows reads the interface's WINUSB compatible ID from the function's descriptors.
  const std::string os_desc = root_ + "/os_desc";
  if (!write_attribute(os_desc + "/use", "1", error) ||
      !write_attribute(os_desc + "/b_vendor_code", hex(usb::kMsVendorCode, 2), error) ||
      !write_attribute(os_desc + "/qw_sign", "MSFT100", error)) {
    return false;
  }
  const std::string os_link = os_desc + "/c.1";
  if (symlink(config.c_str(), os_link.c_str()) != 0 && errno != EEXIST) {
    *error = os_link + ": " + std::strerror(errno);
    return false;
  }
  made_.push_back(os_link);
  mkdir(settings.mount_dir.c_str(), 0755);
  if (mount(settings.name.c_str(), settings.mount_dir.c_str(), "functionfs", 0, nullptr) != 0) {
    *error = "cannot mount FunctionFS '" + settings.name + "' at " + settings.mount_dir + ": " + std::strerror(errno) +
             " (is usb_f_fs loaded?)";
    return false;
  }
  mounted_ = true;
  return true;
}

bool ConfigfsGadget::bind(std::string* error) {
  udc_ = settings_.udc.empty() ? first_udc() : settings_.udc;
  if (udc_.empty()) {
    *error = "no USB device controller (/sys/class/udc is empty): this board has no device port, or its driver "
             "(dwc2 on a Raspberry Pi, dummy_hcd for tests) is not loaded";
    return false;
  }
  if (!write_attribute(root_ + "/UDC", udc_, error)) return false;
  bound_ = true;
  return true;
}

ConfigfsGadget::~ConfigfsGadget() {
  std::string ignored;
  if (bound_) write_attribute(root_ + "/UDC", "\n", &ignored);
  if (mounted_) umount(settings_.mount_dir.c_str());
  for (auto it = made_.rbegin(); it != made_.rend(); ++it) {
    if (unlink(it->c_str()) != 0) rmdir(it->c_str());
  }
}

}  // namespace dg::gadget

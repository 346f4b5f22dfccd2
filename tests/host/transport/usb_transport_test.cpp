// usb: URIs and the answers when no device is there. The bulk transfers themselves run against a
// real USB stack in the Linux-gadget system tests; this machine may have no USB at all.
#include "host/transport/usb_transport.h"

#include <CppUTest/TestHarness.h>

#include <cstdlib>

using namespace dg::host;

TEST_GROUP(UsbTransport) {
  void teardown() override { unsetenv("DIGITIZER_USB_ID"); }
};

TEST(UsbTransport, DefaultsToTheTestIds) {
  const UsbSelector s = parse_usb_uri("usb:");
  LONGS_EQUAL(0x1209, s.vendor);
  LONGS_EQUAL(0x0001, s.product);
  CHECK(s.serial.empty());
}

TEST(UsbTransport, TakesIdsAndASerialFromTheUri) {
  UsbSelector s = parse_usb_uri("usb:16c0:05dc");
  LONGS_EQUAL(0x16c0, s.vendor);
  LONGS_EQUAL(0x05dc, s.product);
  s = parse_usb_uri("usb:serial=DG-0042");
  LONGS_EQUAL(0x1209, s.vendor);
  STRCMP_EQUAL("DG-0042", s.serial.c_str());
  s = parse_usb_uri("usb:1209:0002,serial=A1");
  LONGS_EQUAL(0x0002, s.product);
  STRCMP_EQUAL("A1", s.serial.c_str());
}

TEST(UsbTransport, TakesDefaultIdsFromTheEnvironment) {
  setenv("DIGITIZER_USB_ID", "cafe:babe", 1);
  const UsbSelector s = parse_usb_uri("usb:");
  LONGS_EQUAL(0xcafe, s.vendor);
  LONGS_EQUAL(0xbabe, s.product);
  setenv("DIGITIZER_USB_ID", "cafe", 1);
  CHECK_THROWS(std::invalid_argument, parse_usb_uri("usb:"));
}

TEST(UsbTransport, RejectsMalformedUris) {
  CHECK_THROWS(std::invalid_argument, parse_usb_uri("usb:12345:0001"));
  CHECK_THROWS(std::invalid_argument, parse_usb_uri("usb:xyz:0001"));
  CHECK_THROWS(std::invalid_argument, parse_usb_uri("usb:1209"));
  CHECK_THROWS(std::invalid_argument, parse_usb_uri("usb:serial="));
  CHECK_THROWS(std::invalid_argument, parse_usb_uri("usbx:"));
}

TEST(UsbTransport, AnAbsentDeviceIsAnErrorSayingWhatWasLookedFor) {
  // IDs no device has: whether or not this machine has USB, opening fails with a message that
  // names the URI (no USB at all: libusb cannot start; USB: nothing matches).
  std::string error;
  try {
    UsbTransport transport("usb:f00d:f00d,serial=none");
  } catch (const TransportError& e) {
    error = e.what();
  }
  STRCMP_CONTAINS("usb:f00d:f00d,serial=none", error.c_str());
  CHECK(error.find("no usable device f00d:f00d with serial none") != std::string::npos ||
        error.find("cannot start libusb") != std::string::npos);
}

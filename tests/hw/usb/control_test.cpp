// Endpoint 0 answers a host's enumeration, configuration and halt handling as chapter 9 asks, and
// stalls what it does not support. The controller is a recording double: these tests are about
// the decisions, the STM32 driver and FunctionFS move the bytes.
#include "hw/usb/control.h"

#include <string>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "hw/usb/descriptors.h"

namespace {

using namespace dg::usb;

class RecordingController : public EndpointControl {
 public:
  void set_address(uint8_t address) override { log.push_back("address " + std::to_string(address)); }
  void set_configured(bool on) override { log.push_back(on ? "open" : "close"); }
  void set_halt(uint8_t endpoint, bool halt) override {
    log.push_back((halt ? "halt " : "clear ") + std::to_string(endpoint));
    (endpoint & 0x80 ? in_halted : out_halted) = halt;
  }
  bool halted(uint8_t endpoint) override { return endpoint & 0x80 ? in_halted : out_halted; }
  std::vector<std::string> log;
  bool in_halted = false, out_halted = false;
};

Setup request(uint8_t type, uint8_t req, uint16_t value, uint16_t index, uint16_t length) {
  const uint8_t bytes[8] = {type, req, static_cast<uint8_t>(value), static_cast<uint8_t>(value >> 8),
                            static_cast<uint8_t>(index), static_cast<uint8_t>(index >> 8),
                            static_cast<uint8_t>(length), static_cast<uint8_t>(length >> 8)};
  return parse_setup(bytes);
}

Setup get_descriptor(uint8_t type, uint8_t index, uint16_t length) {
  return request(0x80, 6, static_cast<uint16_t>(type << 8 | index), 0, length);
}

}  // namespace

TEST_GROUP(UsbControl) {
  RecordingController controller;
  ControlRequests ep0{controller, "3A0042001851333035383231"};

  void enumerate() {
    LONGS_EQUAL(ControlReply::kNoData, ep0.setup(request(0x00, 5, 7, 0, 0)).kind);
    LONGS_EQUAL(ControlReply::kNoData, ep0.setup(request(0x00, 9, 1, 0, 0)).kind);
  }
};

TEST(UsbControl, ParsesSetupFieldsLittleEndian) {
  const uint8_t bytes[8] = {0xC0, 0x20, 0x34, 0x12, 0x07, 0x00, 0xFF, 0x00};
  const Setup s = parse_setup(bytes);
  LONGS_EQUAL(0xC0, s.request_type);
  LONGS_EQUAL(0x20, s.request);
  LONGS_EQUAL(0x1234, s.value);
  LONGS_EQUAL(7, s.index);
  LONGS_EQUAL(255, s.length);
}

TEST(UsbControl, AnswersLinuxsFirst64ByteDeviceRequestWithEighteenBytes) {
  const ControlReply reply = ep0.setup(get_descriptor(kDeviceDescriptor, 0, 64));
  LONGS_EQUAL(ControlReply::kData, reply.kind);
  LONGS_EQUAL(18, reply.size);
  MEMCMP_EQUAL(device_descriptor().data, reply.data, 18);
}

TEST(UsbControl, CutsEveryReplyToTheRequestedLength) {
  const ControlReply head = ep0.setup(get_descriptor(kConfigurationDescriptor, 0, 9));
  LONGS_EQUAL(9, head.size);
  const ControlReply all = ep0.setup(get_descriptor(kConfigurationDescriptor, 0, 255));
  LONGS_EQUAL(configuration_descriptor().size, all.size);
  LONGS_EQUAL(2, ep0.setup(get_descriptor(kStringDescriptor, kSerial, 2)).size);
}

TEST(UsbControl, SerialStringIsTheBoardsId) {
  const ControlReply reply = ep0.setup(get_descriptor(kStringDescriptor, kSerial, 255));
  LONGS_EQUAL(ControlReply::kData, reply.kind);
  LONGS_EQUAL(2 + 2 * 24, reply.size);
  LONGS_EQUAL('3', reply.data[2]);
  LONGS_EQUAL('1', reply.data[reply.size - 2]);
}

TEST(UsbControl, SetAddressThenSetConfigurationOpensTheBulkEndpoints) {
  enumerate();
  LONGS_EQUAL(2, controller.log.size());
  STRCMP_EQUAL("address 7", controller.log[0].c_str());
  STRCMP_EQUAL("open", controller.log[1].c_str());
  LONGS_EQUAL(1, ep0.configuration());
  const ControlReply config = ep0.setup(request(0x80, 8, 0, 0, 1));
  LONGS_EQUAL(1, config.size);
  LONGS_EQUAL(1, config.data[0]);
}

TEST(UsbControl, RefusesConfigurationBeforeAnAddressAndUnknownConfigurations) {
  LONGS_EQUAL(ControlReply::kStall, ep0.setup(request(0x00, 9, 1, 0, 0)).kind);
  ep0.setup(request(0x00, 5, 3, 0, 0));
  LONGS_EQUAL(ControlReply::kStall, ep0.setup(request(0x00, 9, 2, 0, 0)).kind);
  LONGS_EQUAL(0, ep0.configuration());
}

TEST(UsbControl, SettingTheConfigurationAgainResetsTheEndpoints) {
  enumerate();
  ep0.setup(request(0x00, 9, 1, 0, 0));
  STRCMP_EQUAL("close", controller.log[2].c_str());
  STRCMP_EQUAL("open", controller.log[3].c_str());
  ep0.setup(request(0x00, 9, 0, 0, 0));
  STRCMP_EQUAL("close", controller.log[4].c_str());
  LONGS_EQUAL(0, ep0.configuration());
}

TEST(UsbControl, HaltAndClearHaltOnTheBulkEndpointsAreReportedByGetStatus) {
  enumerate();
  LONGS_EQUAL(ControlReply::kNoData, ep0.setup(request(0x02, 3, 0, kBulkInEndpoint, 0)).kind);
  CHECK(controller.in_halted);
  ControlReply status = ep0.setup(request(0x82, 0, 0, kBulkInEndpoint, 2));
  LONGS_EQUAL(2, status.size);
  LONGS_EQUAL(1, status.data[0]);
  // libusb_clear_halt sends CLEAR_FEATURE(ENDPOINT_HALT).
  ep0.setup(request(0x02, 1, 0, kBulkInEndpoint, 0));
  CHECK_FALSE(controller.in_halted);
  status = ep0.setup(request(0x82, 0, 0, kBulkInEndpoint, 2));
  LONGS_EQUAL(0, status.data[0]);
}

TEST(UsbControl, StallsEndpointRequestsForEndpointsThatDoNotExist) {
  LONGS_EQUAL(ControlReply::kStall, ep0.setup(request(0x02, 3, 0, kBulkInEndpoint, 0)).kind);  // not configured
  enumerate();
  LONGS_EQUAL(ControlReply::kStall, ep0.setup(request(0x02, 3, 0, 0x82, 0)).kind);
  LONGS_EQUAL(ControlReply::kStall, ep0.setup(request(0x82, 0, 0, 0x03, 2)).kind);
  LONGS_EQUAL(ControlReply::kData, ep0.setup(request(0x82, 0, 0, 0x80, 2)).kind);  // endpoint 0
}

TEST(UsbControl, FullSpeedDeviceRefusesTheDeviceQualifierAndUnknownRequests) {
  LONGS_EQUAL(ControlReply::kStall, ep0.setup(get_descriptor(kDeviceQualifierDescriptor, 0, 10)).kind);
  LONGS_EQUAL(ControlReply::kStall, ep0.setup(get_descriptor(kStringDescriptor, 42, 255)).kind);
  LONGS_EQUAL(ControlReply::kStall, ep0.setup(request(0x00, 3, 1, 0, 0)).kind);  // remote wake-up
  LONGS_EQUAL(ControlReply::kStall, ep0.setup(request(0x21, 0x22, 0, 0, 0)).kind);  // a class request
  LONGS_EQUAL(ControlReply::kStall, ep0.setup(request(0x00, 5, 200, 0, 0)).kind);  // address > 127
}

TEST(UsbControl, VendorRequestReturnsTheMsOs20SetOnlyForItsIndex) {
  const ControlReply set = ep0.setup(request(0xC0, kMsVendorCode, 0, kMsOs20DescriptorIndex, 0xFFFF));
  LONGS_EQUAL(ControlReply::kData, set.kind);
  LONGS_EQUAL(ms_os_20_descriptor_set().size, set.size);
  LONGS_EQUAL(ControlReply::kStall, ep0.setup(request(0xC0, kMsVendorCode, 0, 4, 0xFF)).kind);
  LONGS_EQUAL(ControlReply::kStall, ep0.setup(request(0xC0, kMsVendorCode + 1, 0, 7, 0xFF)).kind);
}

TEST(UsbControl, InterfaceRequestsNeedTheConfigurationAndTheOneAlternateSetting) {
  LONGS_EQUAL(ControlReply::kStall, ep0.setup(request(0x81, 10, 0, 0, 1)).kind);
  enumerate();
  const ControlReply alt = ep0.setup(request(0x81, 10, 0, 0, 1));
  LONGS_EQUAL(1, alt.size);
  LONGS_EQUAL(0, alt.data[0]);
  controller.in_halted = true;
  LONGS_EQUAL(ControlReply::kNoData, ep0.setup(request(0x01, 11, 0, 0, 0)).kind);
  CHECK_FALSE(controller.in_halted);
  LONGS_EQUAL(ControlReply::kStall, ep0.setup(request(0x01, 11, 1, 0, 0)).kind);
}

TEST(UsbControl, BusResetReturnsToTheDefaultState) {
  enumerate();
  ep0.bus_reset();
  STRCMP_EQUAL("close", controller.log.back().c_str());
  LONGS_EQUAL(0, ep0.configuration());
  LONGS_EQUAL(ControlReply::kStall, ep0.setup(request(0x00, 9, 1, 0, 0)).kind);  // address is 0 again
}

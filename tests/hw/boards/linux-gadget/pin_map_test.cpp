// The Linux-gadget board's pin map: the reference Raspberry Pi wiring and --pin changes to it.
#include <CppUTest/TestHarness.h>

#include <string>

#include "hw/boards/linux-gadget/pin_map.h"

using dg::gadget::apply_pin;
using dg::gadget::PinMap;
using dg::gadget::raspberry_pi_pins;
using dg::hal::Pin;

namespace {
int at(Pin pin) { return static_cast<int>(pin); }
}  // namespace

TEST_GROUP(PinMap) {
  PinMap map = raspberry_pi_pins();
  std::string error;
};

TEST(PinMap, TheReferenceWiringUsesDistinctPiLinesForEveryPin) {
  for (int a = 0; a < dg::gadget::kPinCount; ++a) {
    CHECK(map.wired[a]);
    CHECK_EQUAL(0u, map.pins[a].name.rfind("GPIO", 0));
    for (int b = a + 1; b < dg::gadget::kPinCount; ++b) CHECK(map.pins[a].name != map.pins[b].name);
    CHECK(map.pins[a].name != map.driver_enable.name);
  }
  STRCMP_EQUAL("GPIO17", map.pins[at(Pin::kStepX)].name.c_str());
  CHECK(map.enable_wired);
  CHECK(map.driver_enable.active_low);  // the drivers' EN is active low
}

TEST(PinMap, APinCanBeMovedInvertedOrLeftUnwired) {
  CHECK(apply_pin("req=gpiochip2:4/active-low", &map, &error));
  STRCMP_EQUAL("gpiochip2", map.pins[at(Pin::kGaugeReq)].chip.c_str());
  CHECK(map.pins[at(Pin::kGaugeReq)].active_low);
  CHECK(apply_pin("touch=none", &map, &error));
  CHECK_FALSE(map.wired[at(Pin::kTouchProbe)]);
  CHECK(apply_pin("enable=none", &map, &error));
  CHECK_FALSE(map.enable_wired);
  CHECK(apply_pin("limit_y=GPIO4", &map, &error));
  STRCMP_EQUAL("GPIO4", map.pins[at(Pin::kLimitYMin)].name.c_str());
}

TEST(PinMap, RejectsUnknownKeysAndBadLinesNamingThem) {
  CHECK_FALSE(apply_pin("stepx=GPIO1", &map, &error));
  CHECK(error.find("stepx") != std::string::npos);
  CHECK_FALSE(apply_pin("step_x", &map, &error));
  CHECK_FALSE(apply_pin("step_x=gpiochip0:zz", &map, &error));
  STRCMP_EQUAL("GPIO17", map.pins[at(Pin::kStepX)].name.c_str());  // unchanged
}
